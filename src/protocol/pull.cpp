#include "protocol/pull.hpp"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "core/error.hpp"
#include "core/progress.hpp"
#include "core/spatial_order.hpp"
#include "protocol/observables.hpp"
#include "protocol/run_report.hpp"
#include "protocol/speed_limit.hpp"

namespace granudrag {

namespace {
Settings pull_settings(const Bed& bed, const PullSpec& spec) {
  Settings s;
  s.dt = bed.dt;
  s.skin = spec.skin;
  s.active = spec.active;
  if (std::isnan(s.active.wake_force)) s.active.wake_force = default_wake_force(bed.contact.kn);
  // Decisions four times per dwell, and before the intruder has moved half a grain diameter.
  s.active.check_interval = std::max(bed.dt, std::min(0.25 * spec.active.sleep_time, 0.5 / spec.speed));
  // At rest relative to V: around a yield pull the grains creep at a few percent of V, and an
  // absolute threshold held them and stiffened the bed; but no faster than sleep_speed_max, as
  // the wake of a fast pull still moving was held too (docs/pour-and-pull.md, active region).
  s.active.sleep_distance = std::min(spec.sleep_speed * spec.speed, spec.sleep_speed_max) *
                            std::max(spec.active.sleep_time, s.active.check_interval);
  return s;
}
}  // namespace

double froude_number(double speed, double diameter) {
  return 2.0 * speed * std::sqrt(2.0 * diameter) / (diameter + 1.0);
}

Pull::Pull(const Bed& bed, const PullSpec& spec)
    : bed_(bed),
      spec_(spec),
      order_(spatial_order(bed.state.particles, bed.box)),
      rank_(inverse_order(order_)),
      intruder_(bed.intruder < 0 ? -1 : static_cast<int>(rank_[bed.intruder])),
      sim_(reordered(bed.state.particles, order_), bed.box, bed.contact, pull_settings(bed, spec)),
      guard_(GuardLimits{}, 0.0) {
  spec_.validate();
  if (bed_.intruder < 0) throw Error("the bed has no intruder to pull: pour it with intruder_diameter > 0");
  {
    // Grains touching the intruder must stay awake: the region reaches past them.
    const double reach = bed_.state.particles.radius[bed_.intruder] + 2.0;
    if (spec_.active.enabled() && spec_.active.radius < reach) {
      std::ostringstream msg;
      msg << "'active_radius' = " << spec_.active.radius << " d does not reach past the grains around the "
          << "intruder: it must be at least D/2 + 2 = " << reach << " d (or 0: off)";
      throw Error(msg.str());
    }
  }
  if (spec_.fresh_start) {
    sim_.particles().v[intruder_] = Vec3(spec_.speed, 0, 0);
    sim_.setup();
  } else {
    sim_.restore(reordered(bed_.state, order_));
    sim_.particles().v[intruder_] = Vec3(spec_.speed, 0, 0);
  }
  // A resumed replica's state (the other constructor) carries its perturbation already.
  if (spec_.perturbation > 0) sim_.particles().v[replica_grain()].x() += spec_.perturbation;
  // A bed at rest has small overlaps; one beyond what the run guard allows at any step is a
  // damaged or mislabelled bed, named as such before anything is blamed on the speed (with
  // keep_going, the guard records it at the first sample instead).
  if (const double deepest = sim_.contacts().deepest_overlap(sim_.particles(), bed_.box);
      deepest > spec_.max_overlap && !spec_.keep_going) {
    std::ostringstream msg;
    msg << "the bed has grains overlapping by " << deepest
        << " d before the first step, beyond 'max_overlap' = " << spec_.max_overlap
        << " d: the bed file is damaged, or its grains were not poured with the contact law "
        << "it records; pour it again (or, if the overlaps are meant, raise max_overlap)";
    throw Error(msg.str());
  }
  check_pull_speed(spec_.speed, bed_, sim_.dt(), spec_.skin, spec_.max_overlap);
  const double distance = spec_.distance > 0 ? spec_.distance : bed_.box.lx;
  record_.samples_per_interval = std::max(1L, std::lround(spec_.sample_interval / sim_.dt()));
  const double steps_wanted = std::ceil(distance / (spec_.speed * sim_.dt()));
  if (!(steps_wanted < 1e13)) {
    std::ostringstream msg;
    msg << "'speed' = " << spec_.speed << " needs " << steps_wanted << " steps of dt = " << sim_.dt()
        << " to cover " << distance << " d; use a larger speed or a shorter distance";
    throw Error(msg.str());
  }
  const long steps = static_cast<long>(steps_wanted);
  const long k = record_.samples_per_interval;
  record_.total_steps = (steps + k - 1) / k * k;
  planned_steps_ = record_.total_steps;
  const Energy e = sim_.energy();
  record_.energy_start = e.total();
  GuardLimits limits;
  limits.max_overlap = spec_.max_overlap;
  // Above the highest grain by more than a grain hit at V could fly (2V: an elastic bounce off
  // the driven intruder, rising (2V)^2 / 2g) and 10 d to spare.
  double top = 0;
  for (const Vec3& x : bed_.state.particles.x) top = std::max(top, x.z());
  limits.z_max = top + 10.0 + 2.0 * spec_.speed * spec_.speed;
  guard_ = RunGuard(limits, record_.energy_start);
  if (spec_.target_error > 0 && spec_.min_distance >= distance) {
    std::ostringstream msg;
    msg << "'min_distance' = " << spec_.min_distance << " d is not below 'distance' = " << distance
        << " d, the most the pull may travel: the target error could never stop it; lower "
           "min_distance or raise distance";
    throw Error(msg.str());
  }
  if (spec_.transient >= 0 && spec_.transient >= distance) {
    std::ostringstream msg;
    msg << "'transient' = " << spec_.transient << " d leaves nothing of a pull of " << distance
        << " d to average; it must be shorter than 'distance'";
    throw Error(msg.str());
  }
}

Pull::Pull(const Bed& bed, const PullSpec& spec, const Simulation::State& state, PullRecord record)
    : Pull(bed, spec) {
  sim_.restore(state);
  record_ = std::move(record);
  // A record written before theta's series (an older checkpoint) has none: its intervals are
  // unknown, and the totals so far are the baseline of the intervals to come (theta_error).
  if (record_.theta_sum_series.size() != record_.time.size() ||
      record_.theta_count_series.size() != record_.time.size()) {
    record_.theta_sum_series.assign(record_.time.size(), NAN);
    record_.theta_count_series.assign(record_.time.size(), NAN);
    if (!record_.time.empty()) {
      record_.theta_sum_series.back() = record_.theta_sum;
      record_.theta_count_series.back() = static_cast<double>(record_.theta_count);
    }
  }
  // A record written before the present contacts' series: its intervals are unknown.
  if (record_.theta_present_sum.size() != record_.time.size() ||
      record_.theta_present_count.size() != record_.time.size()) {
    record_.theta_present_sum.assign(record_.time.size(), NAN);
    record_.theta_present_count.assign(record_.time.size(), NAN);
  }
  guard_ = RunGuard(guard_.limits(), record_.energy_start);
  guard_.restore(record_.max_overlap, record_.grains_lost);
}

double Pull::transient_distance() const {
  const double distance = planned_steps_ * sim_.dt() * spec_.speed;
  if (spec_.transient >= 0) return std::min(spec_.transient, distance);
  const double D = 2 * bed_.state.particles.radius[bed_.intruder];
  return std::min(D + 1.0, 0.25 * distance);
}

void Pull::run(bool show_progress, const std::function<void(const Pull&)>& on_checkpoint,
               const std::function<void(const Pull&)>& on_frame) {
  long every = spec_.checkpoint_every;
  const long k = record_.samples_per_interval;
  if (every > 0) every = (every + k - 1) / k * k;
  Progress progress("pull", record_.total_steps, sim_.steps_done());
  const double n = static_cast<double>(sim_.particles().size());
  Timers& timers = sim_.timers();
  timers.reset();
  const long first_step = sim_.steps_done();
  const long half = first_step + (record_.total_steps - first_step) / 2;
  const double t0 = omp_get_wtime();
  double t_half = t0;
  const bool dump = spec_.dump_every > 0 && on_frame;
  auto frame = [&] {
    timers.start();
    on_frame(*this);
    ++record_.frames;
    timers.stamp(Phase::IO);
  };
  if (dump && record_.frames == 0) frame();
  while (sim_.steps_done() < record_.total_steps) {
    sim_.step();
    after_step();
    if (sim_.steps_done() % k == 0) end_of_interval();
    timers.stamp(Phase::Observables);
    if (dump && sim_.steps_done() % spec_.dump_every == 0) frame();
    if (every > 0 && sim_.steps_done() % every == 0 && !finished() && on_checkpoint) {
      sim_.rebuild_lists();
      on_checkpoint(*this);
      timers.stamp(Phase::IO);
    }
    if (sim_.steps_done() == half) t_half = omp_get_wtime();
    if (show_progress) progress.update(sim_.steps_done(), n, "particle-steps");
  }
  const double t_end = omp_get_wtime();
  loop_seconds_ = t_end - t0;
  loop_steps_ = sim_.steps_done() - first_step;
  half_seconds_ = t_end - t_half;
  half_steps_ = sim_.steps_done() - std::max(half, first_step);
  if (record_.stop_reason.empty()) record_.stop_reason = "distance";
}

int Pull::replica_grain() const {
  const Particles& p = bed_.state.particles;
  const Vec3& centre = p.x[bed_.intruder];
  int nearest = -1;
  double best = HUGE_VAL;
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (p.species[i] != Species::Mobile) continue;
    const double d2 = bed_.box.min_image(p.x[i] - centre).squaredNorm();
    if (d2 < best) best = d2, nearest = static_cast<int>(i);
  }
  if (nearest < 0) throw Error("'perturbation' needs a mobile grain to perturb, and the bed has none");
  return static_cast<int>(rank_[nearest]);
}

std::string Pull::timing_report() const {
  const double n = static_cast<double>(sim_.particles().size());
  std::ostringstream half;
  half << "timing: second half " << half_seconds_ << " s for " << half_steps_ << " steps, "
       << n * static_cast<double>(half_steps_) / std::max(half_seconds_, 1e-9) << " particle-steps/s\n";
  return timing_line(sim_.timers(), n, loop_steps_, loop_seconds_) + half.str();
}

long Pull::samples_in_transient() const {
  // An interval counts when it starts after the transient; the samples are in time order.
  const double t0 = transient_distance() / spec_.speed;
  long k = 0;
  while (k < static_cast<long>(record_.time.size()) &&
         record_.time[k] - record_.samples_per_interval * sim_.dt() < t0 - 1e-12)
    ++k;
  return k;
}

namespace {
constexpr double kMinStoppingDof = 10;
}

bool stopping_check_due(long n) {
  if (n < 16) return false;
  long power = 1;  // the largest power of 2 not above n
  while (power <= n / 2) power *= 2;
  return n % (power / 16) == 0;
}

bool Pull::target_met() const {
  const double travelled = sim_.steps_done() * sim_.dt() * spec_.speed;
  if (travelled < spec_.min_distance) return false;
  const long first = samples_in_transient();
  if (!stopping_check_due(static_cast<long>(record_.fx.size()) - first)) return false;
  std::vector<double> fx(record_.fx.begin() + first, record_.fx.end());
  const MeanError e = mean_error(fx);
  // Without a plateau the error is the larger of two windows' (protocol/observables.hpp), an
  // overestimate rather than an underestimate, so it may stop the pull too; enough
  // independent samples (dof) keep a lucky early estimate from doing so.
  return e.dof >= kMinStoppingDof && e.error <= spec_.target_error * std::abs(e.mean);
}

void Pull::after_step() {
  const Particles& p = sim_.particles();
  const int in = intruder_;
  record_.force_sum += p.f[in];
  record_.contact_sum += sim_.contacts().contacts_of(in);
  record_.work += -p.f[in].dot(p.v[in]) * sim_.dt();
  const double travelled = sim_.steps_done() * sim_.dt() * spec_.speed;
  if (travelled < transient_distance()) return;
  sim_.contacts().new_contacts_of(in, scratch_);
  for (int g : scratch_) {
    const double theta = contact_angle(g);
    record_.theta_sum += theta;
    ++record_.theta_count;
    const int bin = std::min(35, static_cast<int>(theta / M_PI * 36));
    ++record_.theta_histogram[bin];
  }
}

double Pull::contact_angle(int grain) const {
  // Angle between the intruder's velocity and the line from intruder to grain (Eq. 6 of the
  // paper writes X - x; its data, theta near pi/2.45 falling with Fr, fit x - X).
  const Particles& p = sim_.particles();
  const Vec3 d = bed_.box.min_image(p.x[grain] - p.x[intruder_]);
  return std::acos(std::clamp(d.x() / d.norm(), -1.0, 1.0));
}

void Pull::end_of_interval() {
  const Particles& p = sim_.particles();
  const int in = intruder_;
  const double k = static_cast<double>(record_.samples_per_interval);
  sim_.contacts().touching_contacts_of(in, scratch_);
  double present = 0;
  for (int g : scratch_) present += contact_angle(g);
  record_.theta_present_sum.push_back(present);
  record_.theta_present_count.push_back(static_cast<double>(scratch_.size()));
  record_.time.push_back(sim_.time());
  record_.fx.push_back(record_.force_sum.x() / k);
  record_.fy.push_back(record_.force_sum.y() / k);
  record_.fz.push_back(record_.force_sum.z() / k);
  record_.contacts.push_back(record_.contact_sum / k);
  record_.theta_sum_series.push_back(record_.theta_sum);
  record_.theta_count_series.push_back(static_cast<double>(record_.theta_count));
  if (const ActiveRegion* region = sim_.active_region())
    record_.sleeping.push_back(static_cast<double>(region->sleeping()));
  record_.force_sum.setZero();
  record_.contact_sum = 0;
  // A failure stops the run here, before a checkpoint could save it.
  const std::string why = guard_.check(sim_, record_.work);
  record_.max_overlap = guard_.max_overlap_seen();
  record_.grains_lost = guard_.grains_lost();
  if (!why.empty()) {
    if (!spec_.keep_going || why.rfind("non-finite", 0) == 0)
      throw Error("the pull stopped: " + why + ". The last good checkpoint, if any, is kept");
    if (record_.verdict.empty()) {
      record_.verdict = why;
      std::fprintf(stderr, "pull: warning: %s; going on (keep_going), the run file records it\n",
                   why.c_str());
    }
  }

  const double travelled = sim_.steps_done() * sim_.dt() * spec_.speed;
  if (travelled < transient_distance()) return;
  if (spec_.target_error > 0 && target_met()) {
    // Stop here: the loop ends at this step, and so does a resumed run (same samples, same check).
    record_.total_steps = sim_.steps_done();
    record_.stop_reason = "target_error";
  }
  counts_.assign(p.size(), 0);
  sim_.contacts().count_contacts(counts_);
  const double R = p.radius[in];
  const long n = static_cast<long>(p.size());
  long histogram[16] = {};
  constexpr int rings = CoordinationShells::rings;
  long ring_grains[rings] = {}, ring_contacts[rings] = {};
#pragma omp parallel for schedule(static) \
    reduction(+ : histogram[:16], ring_grains[:rings], ring_contacts[:rings])
  for (long i = 0; i < n; ++i) {
    if (p.species[i] != Species::Mobile) continue;
    const double r = bed_.box.min_image(p.x[i] - p.x[in]).norm();
    if (r < R + spec_.shell) ++histogram[std::min(15, counts_[i])];
    const int k = CoordinationShells::ring(r - R);
    if (k >= 0) {
      ++ring_grains[k];
      ring_contacts[k] += counts_[i];
    }
  }
  for (int z = 0; z < 16; ++z) record_.z_histogram[z] += histogram[z];
  for (int k = 0; k < rings; ++k) {
    record_.shells.grains[k] += ring_grains[k];
    record_.shells.contacts[k] += ring_contacts[k];
  }
  // Snapshots evenly spread over the part of the pull after the transient.
  const long done = static_cast<long>(record_.snapshots.size());
  const double t_end = planned_steps_ * sim_.dt();
  const double t_start = transient_distance() / spec_.speed;
  if (done < spec_.snapshots && sim_.time() >= t_start + (t_end - t_start) * (done + 0.5) / spec_.snapshots) {
    Snapshot s;
    s.time = sim_.time();
    for (std::size_t i : rank_) {  // in the bed's order
      if (p.species[i] != Species::Mobile) continue;
      const Vec3 d = bed_.box.min_image(p.x[i] - p.x[in]);
      if (std::abs(d.y()) >= spec_.slab_half_width) continue;
      s.dx.push_back(d.x());
      s.dz.push_back(d.z());
      s.vx.push_back(p.v[i].x() - spec_.speed);
      s.vz.push_back(p.v[i].z());
    }
    record_.snapshots.push_back(std::move(s));
  }
}

Particles Pull::particles_in_bed_order() const { return reordered(sim_.particles(), rank_); }

// Per interval after the transient (those ending past t0: the angles are counted from t0 on),
// the angles' sum and count, and ratio_error of them. A checkpoint written before the series
// leaves NaN over its intervals: the error then comes from the intervals after the resume,
// scaled by sqrt(their count / all), as a standard error of count items scales.
MeanError Pull::theta_error(double t0) const {
  std::vector<double> sums, counts;
  double before_sum = 0, before_count = 0;
  for (std::size_t k = 0; k < record_.time.size(); ++k) {
    const double s = record_.theta_sum_series[k], c = record_.theta_count_series[k];
    if (record_.time[k] > t0 && std::isfinite(s) && std::isfinite(before_sum)) {
      sums.push_back(s - before_sum);
      counts.push_back(c - before_count);
    }
    before_sum = s, before_count = c;
  }
  MeanError e = ratio_error(sums, counts);
  double covered = 0;
  for (double c : counts) covered += c;
  if (covered > 0 && covered < record_.theta_count)
    e.error *= std::sqrt(covered / static_cast<double>(record_.theta_count));
  e.mean = record_.theta_sum / record_.theta_count;
  return e;
}

PullResult Pull::result() const {
  PullResult r;
  const double D = 2 * bed_.state.particles.radius[bed_.intruder];
  r.froude = froude_number(spec_.speed, D);
  r.transient_distance = transient_distance();
  const double t0 = r.transient_distance / spec_.speed;
  std::vector<double> fx, n, present_sums, present_counts;
  for (std::size_t k = 0; k < record_.time.size(); ++k) {
    // An interval counts when it starts after the transient.
    if (record_.time[k] - record_.samples_per_interval * sim_.dt() < t0 - 1e-12) {
      ++r.transient_samples;
      continue;
    }
    fx.push_back(-record_.fx[k]);
    n.push_back(record_.contacts[k]);
    if (std::isfinite(record_.theta_present_sum[k])) {
      present_sums.push_back(record_.theta_present_sum[k]);
      present_counts.push_back(record_.theta_present_count[k]);
    }
  }
  std::vector<double> resistance(record_.fx.size());
  for (std::size_t k = 0; k < resistance.size(); ++k) resistance[k] = -record_.fx[k];
  r.cumulative_drag = cumulative_average(resistance);
  // The whole series is the last prefix: its error is computed once.
  r.drag_convergence = prefix_errors(fx);
  const MeanError drag = r.drag_convergence.empty() ? mean_error(fx) : r.drag_convergence.back().estimate;
  r.drag = drag.mean;
  r.drag_error = drag.error;
  r.drag_dof = drag.dof;
  r.drag_plateau = drag.plateau;
  r.travel_per_sample = static_cast<double>(record_.samples_per_interval) * sim_.dt() * spec_.speed;
  const MeanError coordination = mean_error(n);
  r.coordination = coordination.mean;
  r.coordination_error = coordination.error;
  if (record_.theta_count > 0) {
    r.theta = record_.theta_sum / record_.theta_count;
    const MeanError e = theta_error(t0);
    r.theta_error = e.error;
    r.theta_dof = e.dof;
  }
  const MeanError present = ratio_error(present_sums, present_counts);
  r.theta_present = present.mean;
  r.theta_present_error = present.error;
  r.theta_present_dof = present.dof;
  long total = 0, weighted = 0;
  for (std::size_t z = 0; z < record_.z_histogram.size(); ++z) {
    total += record_.z_histogram[z];
    weighted += static_cast<long>(z) * record_.z_histogram[z];
  }
  if (total > 0) {
    r.bulk_coordination = static_cast<double>(weighted) / total;
    for (long c : record_.z_histogram) r.z_distribution.push_back(static_cast<double>(c) / total);
  }
  const double per_contact = (D + 1) * (D + 1) / (2 * std::sqrt(3.0));
  r.kappa = r.bulk_coordination / r.coordination * per_contact;
  r.shell_z = record_.shells.z();
  for (double z : r.shell_z) r.shell_kappa.push_back(z / r.coordination * per_contact);
  return r;
}

int Pull::grains_lost() const {
  const Particles& p = sim_.particles();
  int lost = 0;
  for (std::size_t i = 0; i < p.size(); ++i)
    if (p.species[i] == Species::Mobile && (!p.x[i].allFinite() || p.x[i].z() < 0)) ++lost;
  return lost;
}

std::string Pull::sanity_report(double wall_seconds) const {
  SanityFigures f;
  f.grains_lost = grains_lost();
  f.grains = static_cast<long>(sim_.particles().count(Species::Mobile));
  f.largest_overlap = record_.max_overlap;
  f.energy_start = record_.energy_start;
  f.energy_end = sim_.energy().total();
  f.work = record_.work;
  f.particle_steps_per_second =
      static_cast<double>(sim_.particles().size()) * sim_.steps_done() / std::max(wall_seconds, 1e-9);
  return sanity_line(f);
}

}  // namespace granudrag
