#include "engine/simulation.hpp"

#include <cmath>
#include <sstream>

#include "contact/brute_force_contacts.hpp"
#include "contact/verlet_contacts.hpp"
#include "core/error.hpp"
#include "core/progress.hpp"

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
}

void Simulation::setup() {
  timers_.start();
  if (contacts_->update_lists(p_, box_, &timers_)) lists_rebuilt();
  timers_.stamp(Phase::Neighbor);
  clear_forces();
  contact_forces(false);
  const long n = static_cast<long>(p_.size());
  for (long i = 0; i < n; ++i) add_body_force(i);
  timers_.stamp(Phase::Force);
  ready_ = true;
}

void Simulation::step() {
  if (!ready_) setup();
  timers_.start();
  initial_integrate();
  timers_.stamp(Phase::Integrate);
  // Stamps Neighbor and History when it rebuilds.
  if (contacts_->update_lists(p_, box_, &timers_)) lists_rebuilt();
  timers_.stamp(Phase::Neighbor);
  contact_forces(true);
  timers_.stamp(Phase::Force);
  final_integrate();
  timers_.stamp(Phase::Integrate);
  ++steps_;
}

void Simulation::run(long steps, bool show_progress) {
  Progress progress("steps", steps);
  for (long s = 0; s < steps; ++s) {
    step();
    if (show_progress && (s % 100 == 0 || s + 1 == steps))
      progress.update(s + 1, static_cast<double>(p_.size()), "particle-steps");
  }
}

// The passes over the bodies are fused: the first half-kick also clears the forces it has used,
// and the second adds gravity before it kicks, so a step reads the arrays twice, not four times.
// Components one by one rather than Vec3 expressions: Eigen packs x, y into one register and z
// into another, and on these short loops the shuffles cost more than the arithmetic.
void Simulation::initial_integrate() {
  const double half = 0.5 * dt_, dt = dt_;
  const long n = static_cast<long>(p_.size());
  double* x = p_.x.data()->data();
  double* v = p_.v.data()->data();
  double* w = p_.omega.data()->data();
  double* f = p_.f.data()->data();
  double* tq = p_.torque.data()->data();
#pragma omp parallel for schedule(static)
  for (long i = 0; i < n; ++i) {
    const Species kind = p_.species[i];
    if (kind == Species::Mobile) {
      const double kick_v = half / p_.mass[i], kick_w = half / p_.inertia(i);
      for (int d = 0; d < 3; ++d) {
        v[3 * i + d] += kick_v * f[3 * i + d];
        x[3 * i + d] += dt * v[3 * i + d];
        w[3 * i + d] += kick_w * tq[3 * i + d];
      }
    } else if (kind == Species::Intruder) {  // prescribed velocity
      for (int d = 0; d < 3; ++d) x[3 * i + d] += dt * v[3 * i + d];
    }
    for (int d = 0; d < 3; ++d) f[3 * i + d] = tq[3 * i + d] = 0.0;
  }
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
  } else if (p_.species[i] == Species::Frozen) {
    double* tq = p_.torque[i].data();
    for (int d = 0; d < 3; ++d) f[d] = tq[d] = 0.0;  // as LAMMPS fix freeze
  }
}

void Simulation::final_integrate() {
  const double half = 0.5 * dt_;
  const long n = static_cast<long>(p_.size());
  double* v = p_.v.data()->data();
  double* w = p_.omega.data()->data();
  const double* f = p_.f.data()->data();
  const double* tq = p_.torque.data()->data();
#pragma omp parallel for schedule(static)
  for (long i = 0; i < n; ++i) {
    add_body_force(i);
    if (p_.species[i] != Species::Mobile) continue;
    const double kick_v = half / p_.mass[i], kick_w = half / p_.inertia(i);
    for (int d = 0; d < 3; ++d) {
      v[3 * i + d] += kick_v * f[3 * i + d];
      w[3 * i + d] += kick_w * tq[3 * i + d];
    }
  }
}

void Simulation::rebuild_lists() {
  if (!ready_) setup();
  contacts_->rebuild(p_, box_);
  lists_rebuilt();
}

void Simulation::lists_rebuilt() {
  // The oracle has no lists (nor displacement checks): it keeps testing every grain.
  if (!settings_.brute_force) wall_.select(p_, settings_.skin);
}

Simulation::State Simulation::state() const {
  return {p_, contacts_->export_history(), wall_.shear(), steps_};
}

void Simulation::restore(const State& s) {
  if (s.particles.size() != p_.size())
    throw Error("state to restore has " + std::to_string(s.particles.size()) + " particles, the simulation " +
                std::to_string(p_.size()));
  p_ = s.particles;
  contacts_->rebuild(p_, box_);
  contacts_->import_history(s.pair_history);
  wall_.restore_shear(s.wall_history);
  lists_rebuilt();
  steps_ = s.steps;
  ready_ = true;  // the forces in s.particles are those of the last step: no setup()
}

Energy Simulation::energy() const {
  Energy e;
  for (std::size_t i = 0; i < p_.size(); ++i) {
    if (p_.species[i] != Species::Mobile) continue;
    e.kinetic += 0.5 * p_.mass[i] * p_.v[i].squaredNorm();
    e.rotational += 0.5 * p_.inertia(i) * p_.omega[i].squaredNorm();
    e.potential -= p_.mass[i] * settings_.gravity.dot(p_.x[i]);
  }
  e.elastic = contacts_->elastic_energy(p_, box_, contact_);
  if (box_.wall) e.elastic += wall_.elastic_energy(p_, contact_);
  return e;
}

}  // namespace granudrag
