#include "engine/simulation.hpp"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <sstream>

#include "contact/brute_force_contacts.hpp"
#include "contact/verlet_contacts.hpp"
#include "core/balanced_split.hpp"
#include "core/error.hpp"
#include "core/ordered_sum.hpp"
#include "core/progress.hpp"
#include "core/spatial_order.hpp"

namespace granudrag {

namespace {
double min_grain_radius(const Particles& p) {
  double r = p.min_radius(Species::Mobile);
  if (!std::isfinite(r)) r = p.min_radius(Species::Frozen);
  if (!std::isfinite(r)) r = 0.5;
  return r;
}
}  // namespace

Simulation::Simulation(Particles particles, Box box, ContactParams contact, Settings settings)
    : p_(std::move(particles)), box_(box), contact_(contact), settings_(settings) {
  contact_.validate();
  if (!(box_.lx > 0) || !(box_.ly > 0))
    throw Error("box size must be positive (got lx = " + std::to_string(box_.lx) +
                ", ly = " + std::to_string(box_.ly) + ")");
  if (!(settings_.skin > 0))
    throw Error("neighbour skin must be > 0 (got " + std::to_string(settings_.skin) + ")");
  const double rmin = min_grain_radius(p_);
  dt_ = settings_.dt > 0 ? settings_.dt : default_time_step(contact_, rmin);
  check_time_step(dt_, contact_, rmin);
  if (settings_.brute_force)
    contacts_ = std::make_unique<BruteForceContacts>();
  else
    contacts_ = std::make_unique<VerletContacts>(settings_.skin);
  if (settings_.active.enabled()) {
    region_ = std::make_unique<ActiveRegion>(settings_.active, dt_, p_);
    contacts_->set_held(&region_->held());
  }
}

void Simulation::setup() {
  timers_.start();
  // Nothing has moved yet, and there are no lists to have moved from: the first build.
  if (contacts_->update_lists(p_, box_, &timers_, HUGE_VAL)) lists_rebuilt();
  timers_.stamp(Phase::Neighbor);
  clear_forces();
  contact_forces(false);
  const long n = static_cast<long>(p_.size());
  for (long i = 0; i < n; ++i) add_body_force(i);
  timers_.stamp(Phase::Force);
  ready_ = true;
}

// One parallel region per step: a fork and a join, and a barrier wherever the data need one
// (positions before forces, the colours of the contact loop, forces before the second kick).
// Each costs when a core is shared, where a thread that is switched out holds up the team
// (issue 29). The lists' rebuild, every few tens of steps, runs parallel regions of its own;
// on those steps the region ends at the rebuild decision and a second one computes the forces.
void Simulation::step() {
  if (!ready_) setup();
  timers_.start();
  ensure_body_split();
  contacts_->prepare_accumulate();
  if (box_.wall) wall_.prepare(p_);
  thread_drift_.assign(omp_get_max_threads(), 0.0);
  damping_ = settings_.viscous_damping > 0 && time() >= settings_.viscous_from;
  double max_drift_sq = 0;
  bool rebuild = false;
#pragma omp parallel
  {
    const int t = omp_get_thread_num(), nt = omp_get_num_threads();
    const auto [first, last] = body_range(t, nt);
    thread_drift_[t] = initial_integrate(first, last);
#pragma omp barrier
    // Every thread reads the same drifts, so all take the same decision.
    const double drift = *std::max_element(thread_drift_.begin(), thread_drift_.begin() + nt);
    const bool due = contacts_->rebuild_due(p_.size(), drift);
#pragma omp masked
    {
      timers_.stamp(Phase::Integrate);
      if (due) {
        max_drift_sq = drift;
        rebuild = true;
      } else {
        timers_.stamp(Phase::Neighbor);
      }
    }
    if (!due) forces_and_final_kick(first, last);
  }
  if (rebuild) {
    // Stamps Neighbor and History.
    if (contacts_->update_lists(p_, box_, &timers_, max_drift_sq)) lists_rebuilt();
    timers_.stamp(Phase::Neighbor);
    contacts_->prepare_accumulate();
#pragma omp parallel
    {
      const auto [first, last] = body_range(omp_get_thread_num(), omp_get_num_threads());
      forces_and_final_kick(first, last);
    }
  }
  ++steps_;
  if (region_ && region_->after_step(p_, box_, steps_, settings_.gravity)) {
    contacts_->held_changed();
    contacts_->held_pair_forces(p_, box_, contact_, region_->held_forces(), region_->held_loads());
    classify_quiet(true);
  }
  timers_.stamp(Phase::Integrate);
}

// By every thread of the step's team, on its bodies first .. last - 1.
void Simulation::forces_and_final_kick(long first, long last) {
  contacts_->accumulate_in_team(p_, box_, contact_, dt_, true);
  // Pairs write the forces of bodies other threads own: all of them are in before any thread
  // completes its bodies' totals and kicks them.
#pragma omp barrier
  contacts_->finish_accumulate(p_, first, last);
  if (box_.wall) wall_.accumulate_range(p_, contact_, dt_, true, first, last);
#pragma omp masked
  timers_.stamp(Phase::Force);
  final_integrate(first, last);
}

void Simulation::run(long steps, bool show_progress) {
  Progress progress("steps", steps);
  for (long s = 0; s < steps; ++s) {
    step();
    if (show_progress && (s % 100 == 0 || s + 1 == steps))
      progress.update(s + 1, static_cast<double>(p_.size()), "particle-steps");
  }
}

// Without the region, or before its first classification, every body in order; with it, from
// its lists of the bodies that are not quiet (a settled bed is mostly quiet, and a pass over
// every body to skip them cost more than the bodies left): the moving ones, then the held ones.
// A body's step reads and writes its own data only, so the order changes no bit.
template <class Body>
void Simulation::for_stepped(long first, long last, Body&& body) {
  if (!stepping_listed()) {
    const std::uint8_t* held = region_ ? region_->held().data() : nullptr;
    for (long i = first; i < last; ++i) body(i, held && held[i]);
    return;
  }
  const std::uint8_t* quiet = region_->quiet().data();
  auto each = [&](const std::vector<int>& listed, auto held) {
    const auto end = std::lower_bound(listed.begin(), listed.end(), last);
    for (auto k = std::lower_bound(listed.begin(), end, first); k != end; ++k)
      if (quiet[*k] != ActiveRegion::kQuiet) body(*k, held);
  };
  each(stepped_moving_, std::false_type{});
  each(stepped_held_, std::true_type{});
}

// The passes over the bodies are fused: the first half-kick also clears the forces it has used
// and measures how far each body has moved since the last list build (the rebuild check), and
// the second adds gravity before it kicks, so a step reads the arrays twice, not four times.
// Components one by one rather than Vec3 expressions: Eigen packs x, y into one register and z
// into another, and on these short loops the shuffles cost more than the arithmetic.
double Simulation::initial_integrate(long first, long last) {
  const double dt = dt_;
  double* x = p_.x.data()->data();
  double* v = p_.v.data()->data();
  double* w = p_.omega.data()->data();
  double* f = p_.f.data()->data();
  double* tq = p_.torque.data()->data();
  // Without lists, or before the first build, there is nothing to measure against.
  const std::vector<Vec3>* reference = contacts_->build_positions();
  const bool measure = reference && reference->size() == p_.size();
  const double* x0 = measure ? reference->data()->data() : nullptr;
  double max_drift_sq = measure ? 0.0 : HUGE_VAL;
  // Quiet grains are not visited: held, nothing but gravity on them, their force stays m g, and
  // they have not moved since the lists were built or since they were last measured.
  for_stepped(first, last, [&](long i, bool held) {  // held: asleep, not moved
    const Species kind = p_.species[i];
    if (kind == Species::Mobile && !held) {
      const double kick_v = kick_v_[i], kick_w = kick_w_[i];
      for (int d = 0; d < 3; ++d) {
        v[3 * i + d] += kick_v * f[3 * i + d];
        x[3 * i + d] += dt * v[3 * i + d];
        w[3 * i + d] += kick_w * tq[3 * i + d];
      }
    } else if (kind == Species::Intruder) {  // prescribed velocity
      for (int d = 0; d < 3; ++d) x[3 * i + d] += dt * v[3 * i + d];
    }
    for (int d = 0; d < 3; ++d) f[3 * i + d] = tq[3 * i + d] = 0.0;
    // A held grain has not moved since it was last measured awake, when its drift was within
    // the limit (or the lists were rebuilt, which zeroed it): it cannot call for a rebuild, and
    // skipping it spares a stream of build positions (a tenth of a region pull's integration).
    if (!measure || held) return;
    const double dx = x[3 * i] - x0[3 * i], dy = x[3 * i + 1] - x0[3 * i + 1],
                 dz = x[3 * i + 2] - x0[3 * i + 2];
    const double d2 = dx * dx + dy * dy + dz * dz;
    // Written so that a NaN displacement wins: the rebuild it forces reports it.
    if (!(d2 <= max_drift_sq)) max_drift_sq = std::isnan(d2) ? HUGE_VAL : d2;
  });
  return max_drift_sq;
}

void Simulation::clear_forces() {
  const long n = static_cast<long>(p_.size());
#pragma omp parallel for schedule(static)
  for (long i = 0; i < n; ++i) {
    p_.f[i].setZero();
    p_.torque[i].setZero();
  }
}

void Simulation::contact_forces(bool update_history) {
  contacts_->accumulate(p_, box_, contact_, dt_, update_history);
  if (box_.wall) wall_.accumulate(p_, contact_, dt_, update_history);
}

inline void Simulation::add_body_force(long i) {
  double* f = p_.f[i].data();
  if (p_.species[i] == Species::Mobile) {
    const double m = p_.mass[i];
    for (int d = 0; d < 3; ++d) f[d] += m * settings_.gravity[d];
    if (damping_) {  // with the half-step velocities, as the contacts' damping
      const double c = m * settings_.viscous_damping, c_spin = p_.inertia(i) * settings_.viscous_damping;
      const double* v = p_.v[i].data();
      const double* w = p_.omega[i].data();
      double* tq = p_.torque[i].data();
      for (int d = 0; d < 3; ++d) {
        f[d] -= c * v[d];
        tq[d] -= c_spin * w[d];
      }
    }
  } else if (p_.species[i] == Species::Frozen) {
    double* tq = p_.torque[i].data();
    for (int d = 0; d < 3; ++d) f[d] = tq[d] = 0.0;  // as LAMMPS fix freeze
  }
}

void Simulation::final_integrate(long first, long last) {
  double* v = p_.v.data()->data();
  double* w = p_.omega.data()->data();
  const double* f = p_.f.data()->data();
  const double* tq = p_.torque.data()->data();
  for_stepped(first, last, [&](long i, bool held) {
    add_body_force(i);
    if (p_.species[i] != Species::Mobile) return;
    if (held) {  // asleep: its force is summed for the wake test, not integrated
      region_->add_force(i, p_.f[i]);
      return;
    }
    const double kick_v = kick_v_[i], kick_w = kick_w_[i];
    for (int d = 0; d < 3; ++d) {
      v[3 * i + d] += kick_v * f[3 * i + d];
      w[3 * i + d] += kick_w * tq[3 * i + d];
    }
  });
}

// A mobile grain costs the integrator several times what a frozen one or an intruder does
// (three kicks and a drift, against clearing its forces; weights 2 and 4 measured alike); a
// plain split of the index range gave the thread holding a poured bed's frozen base (its first
// grains) a tenth less work. With the region's lists only the bodies listed cost: the awake ones
// lie in a few places of the index range (the region and the failure zone above it), and a split
// by species gave one of two threads most of them (the integration 1.28x faster on 2 threads
// than on 1, in a yield pull through a 70k bed with 84 % asleep). A held grain costs about half
// an awake one (its forces cleared, its weight added and summed for the wake test).
void Simulation::balance_bodies(int threads) {
  constexpr long kMobileCost = 4, kHeldCost = 2;
  const long n = static_cast<long>(p_.size());
  auto cost_of = [&](long i) { return p_.species[i] == Species::Mobile ? kMobileCost : 1; };
  std::vector<long> cost(n + 1, 0);
  if (stepping_listed()) {
    for (int i : stepped_moving_) cost[i + 1] = cost_of(i);
    for (int i : stepped_held_) cost[i + 1] = p_.species[i] == Species::Mobile ? kHeldCost : 1;
  } else {
    for (long i = 0; i < n; ++i) cost[i + 1] = cost_of(i);
  }
  for (long i = 0; i < n; ++i) cost[i + 1] += cost[i];
  balanced_split(cost, threads, body_split_);
}

bool Simulation::stepping_listed() const {
  return region_ && !(stepped_moving_.empty() && stepped_held_.empty());
}

// The half-kicks' factors, kept rather than divided out twice per body and step (masses and
// radii are fixed for a run; the arrays follow the bodies at every list build and restore).
void Simulation::compute_kicks() {
  const long n = static_cast<long>(p_.size());
  const double half = 0.5 * dt_;
  kick_v_.resize(n);
  kick_w_.resize(n);
  for (long i = 0; i < n; ++i) {
    kick_v_[i] = half / p_.mass[i];
    kick_w_[i] = half / p_.inertia(i);
  }
}

void Simulation::ensure_body_split() {
  const int threads = omp_get_max_threads();
  if (kick_v_.size() != p_.size()) compute_kicks();
  if (static_cast<int>(body_split_.size()) != threads + 1 ||
      body_split_.back() != static_cast<long>(p_.size()))
    balance_bodies(threads);
}

std::pair<long, long> Simulation::body_range(int thread, int threads) const {
  if (static_cast<int>(body_split_.size()) == threads + 1)
    return {body_split_[thread], body_split_[thread + 1]};
  // A smaller team than planned (nested or limited): an even split of the index range.
  const long n = static_cast<long>(p_.size());
  return {n * thread / threads, n * (thread + 1) / threads};
}

void Simulation::rebuild_lists() {
  if (!ready_) setup();
  contacts_->rebuild(p_, box_);
  lists_rebuilt();
}

void Simulation::lists_rebuilt() {
  // The oracle has no lists (nor displacement checks): it keeps testing every grain.
  if (!settings_.brute_force) wall_.select(p_, settings_.skin);
  // Species may have changed since (a base frozen through particles()), and the bodies are
  // reordered at builds.
  compute_kicks();
  if (region_)
    classify_quiet(false);  // balances the bodies for the lists it makes
  else
    balance_bodies(omp_get_max_threads());
}

void Simulation::classify_quiet(bool promote) {
  // At a list build only quiet grains can change (back to stepped): with none, and every body
  // stepped already, the pass over every pair would change nothing. Every body is then stepped
  // unlisted, held or not as the region says now (a restored state may hold others).
  const std::vector<std::uint8_t>& quiet = region_->quiet();
  const std::size_t listed = stepped_moving_.size() + stepped_held_.size();
  const bool all_stepped = listed == 0 || listed == p_.size();
  if (!promote && all_stepped &&
      std::none_of(quiet.begin(), quiet.end(), [](std::uint8_t q) { return q != 0; })) {
    stepped_moving_.clear();
    stepped_held_.clear();
    balance_bodies(omp_get_max_threads());
    return;
  }
  std::vector<std::uint8_t> exposed(p_.size(), 0);
  contacts_->mark_exposed(exposed);
  if (box_.wall) wall_.mark_near(exposed);
  region_->classify_quiet(p_, exposed, promote, settings_.gravity);
  // Grains turning quiet stay listed until the next classification (for_stepped skips them).
  const std::uint8_t* held = region_->held().data();
  stepped_moving_.clear();
  stepped_held_.clear();
  for (std::size_t i = 0; i < quiet.size(); ++i)
    if (quiet[i] != ActiveRegion::kQuiet)
      (held[i] ? stepped_held_ : stepped_moving_).push_back(static_cast<int>(i));
  balance_bodies(omp_get_max_threads());
}

Simulation::State Simulation::state() const {
  return {p_, contacts_->export_history(), wall_.shear(), steps_,
          region_ ? region_->state() : ActiveRegion::State{}};
}

void Simulation::restore(const State& s) {
  if (s.particles.size() != p_.size())
    throw Error("state to restore has " + std::to_string(s.particles.size()) + " particles, the simulation " +
                std::to_string(p_.size()));
  p_ = s.particles;
  // The region's mask first: the rebuild sorts the contact loop's rows by it. A bed's state
  // carries none (nothing asleep yet).
  if (!s.region.held.empty()) {
    if (!region_) throw Error("the state to restore has an active region, and this simulation has none");
    region_->restore(s.region, p_);
  }
  contacts_->rebuild(p_, box_);
  contacts_->import_history(s.pair_history);
  wall_.restore_shear(s.wall_history);
  lists_rebuilt();
  steps_ = s.steps;
  ready_ = true;  // the forces in s.particles are those of the last step: no setup()
}

Energy Simulation::energy() const {
  // In parallel: the run guard asks for it every sample interval.
  Energy e = ordered_sum<Energy>(static_cast<long>(p_.size()), [&](long i) {
    Energy b;
    if (p_.species[i] != Species::Mobile) return b;
    b.kinetic = 0.5 * p_.mass[i] * p_.v[i].squaredNorm();
    b.rotational = 0.5 * p_.inertia(i) * p_.omega[i].squaredNorm();
    b.potential = -p_.mass[i] * settings_.gravity.dot(p_.x[i]);
    return b;
  });
  e.elastic = contacts_->elastic_energy(p_, box_, contact_);
  if (box_.wall) e.elastic += wall_.elastic_energy(p_, contact_);
  return e;
}

namespace {
template <class T>
std::vector<T> permuted(const std::vector<T>& a, const std::vector<std::size_t>& order) {
  if (a.empty()) return a;
  if (a.size() != order.size())
    throw Error("a per-body array of " + std::to_string(a.size()) + " entries for " +
                std::to_string(order.size()) + " bodies");
  std::vector<T> out(order.size());
  for (std::size_t k = 0; k < order.size(); ++k) out[k] = a[order[k]];
  return out;
}
}  // namespace

Simulation::State reordered(const Simulation::State& s, const std::vector<std::size_t>& order) {
  if (order.size() != s.particles.size())
    throw Error("an order of " + std::to_string(order.size()) + " bodies for a state of " +
                std::to_string(s.particles.size()));
  const std::vector<std::size_t> rank = inverse_order(order);
  Simulation::State r;
  r.particles = reordered(s.particles, order);
  r.pair_history.reserve(s.pair_history.size());
  for (const PairHistory& h : s.pair_history) {
    const int i = static_cast<int>(rank[h.i]), j = static_cast<int>(rank[h.j]);
    r.pair_history.push_back(i < j ? PairHistory{i, j, h.shear} : PairHistory{j, i, Vec3(-h.shear)});
  }
  r.wall_history = permuted(s.wall_history, order);
  r.steps = s.steps;
  const ActiveRegion::State& a = s.region;
  r.region = a;
  r.region.held = permuted(a.held, order);
  r.region.at_rest = permuted(a.at_rest, order);
  r.region.anchor = permuted(a.anchor, order);
  r.region.force_sum = permuted(a.force_sum, order);
  r.region.held_force = permuted(a.held_force, order);
  r.region.held_load = permuted(a.held_load, order);
  r.region.reference = permuted(a.reference, order);
  r.region.reference_due = permuted(a.reference_due, order);
  r.region.quiet = permuted(a.quiet, order);
  return r;
}

}  // namespace granudrag
