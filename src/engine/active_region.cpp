#include "engine/active_region.hpp"

#include <algorithm>
#include <cmath>

#include "core/error.hpp"

namespace granudrag {

double default_wake_force(double kn) {
  constexpr double kn_validated = 2e5, at_validated = 0.5, per_decade = 4.0;
  return kn <= kn_validated ? at_validated
                            : at_validated * std::pow(per_decade, std::log10(kn / kn_validated));
}

ActiveRegion::ActiveRegion(const ActiveRegionSettings& settings, double dt, const Particles& p)
    : settings_(settings), dt_(dt) {
  if (!(settings_.radius > 0) || !(settings_.sleep_distance > 0) || !(settings_.sleep_time >= 0) ||
      !(settings_.wake_force > 0) || !(settings_.wake_load >= 0) || !(settings_.check_interval > 0))
    throw Error(
        "active region: active_radius, sleep_distance, wake_force and the check interval must be > 0, "
        "sleep_time and wake_load >= 0 (an unset wake_force is resolved by the pull: default_wake_force)");
  check_steps_ = std::max(1L, std::lround(settings_.check_interval / dt));
  dwell_checks_ = static_cast<std::int32_t>(
      std::clamp(std::ceil(settings_.sleep_time / (check_steps_ * dt) - 1e-9), 1.0, 1e9));
  const std::size_t n = p.size();
  s_.held.assign(n, 0);
  s_.at_rest.assign(n, 0);
  s_.anchor = p.x;
  s_.force_sum.assign(n, Vec3::Zero());
  s_.held_force.assign(n, Vec3::Zero());
  if (settings_.wake_load > 0) s_.held_load.assign(n, 0.0);
  s_.reference.assign(n, Vec3::Zero());
  s_.reference_due.assign(n, 0);
  s_.quiet.assign(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    if (p.species[i] == Species::Frozen) s_.held[i] = 1;
    if (p.species[i] == Species::Intruder) intruders_.push_back(static_cast<int>(i));
  }
}

double ActiveRegion::distance_to_intruders(const Particles& p, const Box& box, const Vec3& x) const {
  double d2 = HUGE_VAL;
  for (int in : intruders_) d2 = std::min(d2, box.min_image(x - p.x[in]).squaredNorm());
  return std::sqrt(d2);
}

bool ActiveRegion::after_step(Particles& p, const Box& box, long step, const Vec3& gravity) {
  ++s_.interval_steps;
  if (step % check_steps_ != 0) return false;

  // Grains are woken before the intruder can reach them: the region reaches as far ahead as
  // the intruder travels until the next check.
  double speed = 0;
  for (int in : intruders_) speed = std::max(speed, p.v[in].norm());
  const double reach = settings_.radius + speed * check_steps_ * dt_;
  const double per_step = 1.0 / static_cast<double>(std::max<std::int64_t>(1, s_.interval_steps));
  const double wake = settings_.wake_force * gravity.norm();
  const double* load = s_.held_load.empty() ? nullptr : s_.held_load.data();
  const double rest = settings_.sleep_distance;
  const long n = static_cast<long>(p.size());
  long woke = 0, slept = 0, sleeping = 0;
#pragma omp parallel for schedule(static) reduction(+ : woke, slept, sleeping)
  for (long i = 0; i < n; ++i) {
    if (p.species[i] != Species::Mobile) continue;
    const bool near = distance_to_intruders(p, box, p.x[i]) < reach;
    if (s_.held[i]) {
      // A quiet grain felt its weight alone at every step of the interval.
      const Vec3 mean = s_.quiet[i] == kQuiet ? Vec3(p.mass[i] * gravity) : Vec3(s_.force_sum[i] * per_step);
      const Vec3 net = mean + s_.held_force[i];
      s_.force_sum[i].setZero();
      if (!near && s_.reference_due[i]) {
        s_.reference[i] = net;
        s_.reference_due[i] = 0;
      }
      const double threshold =
          load ? std::max(wake * p.mass[i], settings_.wake_load * load[i]) : wake * p.mass[i];
      if (near || (net - s_.reference[i]).norm() > threshold) {
        s_.held[i] = 0;
        s_.quiet[i] = 0;
        s_.at_rest[i] = 0;
        s_.anchor[i] = p.x[i];
        ++woke;
      } else {
        ++sleeping;
      }
      continue;
    }
    const bool at_rest = !near && box.min_image(p.x[i] - s_.anchor[i]).norm() < rest;
    if (!at_rest) {
      s_.at_rest[i] = 0;
      s_.anchor[i] = p.x[i];
      continue;
    }
    if (++s_.at_rest[i] < dwell_checks_) continue;
    s_.held[i] = 1;
    s_.reference_due[i] = 1;
    s_.force_sum[i].setZero();
    p.v[i].setZero();
    p.omega[i].setZero();
    ++slept;
    ++sleeping;
  }
  s_.interval_steps = 0;
  sleeping_ = sleeping;
  s_.wake_ups += woke;
  s_.sleeps += slept;
  return woke + slept > 0;
}

void ActiveRegion::classify_quiet(Particles& p, const std::vector<std::uint8_t>& exposed, bool promote,
                                  const Vec3& gravity) {
  if (!settings_.skip_quiet) return;
  const long n = static_cast<long>(p.size());
  const double steps = static_cast<double>(s_.interval_steps);
#pragma omp parallel for schedule(static)
  for (long i = 0; i < n; ++i) {
    if (s_.quiet[i]) {
      if (!exposed[i]) continue;
      if (s_.quiet[i] == kQuiet) {
        // Stepped again from now: its force sum so far is its weight at every step, and its
        // force is accumulated afresh (a list build comes after the first half-kick cleared it).
        s_.force_sum[i] = p.mass[i] * gravity * steps;
        p.f[i].setZero();
        p.torque[i].setZero();
      }
      s_.quiet[i] = 0;
    } else if (promote && s_.held[i] && !exposed[i] && p.species[i] == Species::Mobile) {
      s_.quiet[i] = kTurningQuiet;
    }
  }
}

void ActiveRegion::restore(const State& s, const Particles& p) {
  const std::size_t n = p.size();
  for (std::size_t size : {s.held.size(), s.at_rest.size(), s.anchor.size(), s.force_sum.size(),
                           s.held_force.size(), s.reference.size(), s.reference_due.size(), s.quiet.size()})
    if (size != n)
      throw Error("the active region's saved state does not match the bed's " + std::to_string(n) +
                  " bodies");
  if (s.held_load.size() != (settings_.wake_load > 0 ? n : 0))
    throw Error(
        settings_.wake_load > 0
            ? "the active region's saved state has no held loads, and this pull's wake_load needs them: "
              "resume with the wake_load the run was started with"
            : "the active region's saved state has held loads (a run with wake_load): resume with "
              "the wake_load the run was started with");
  s_ = s;
  sleeping_ = 0;
  for (std::size_t i = 0; i < n; ++i) sleeping_ += s_.held[i] && p.species[i] == Species::Mobile;
}

}  // namespace granudrag
