#include "engine/run_guard.hpp"

#include <cmath>
#include <sstream>

namespace granudrag {

ParameterSpec max_overlap_key() {
  return Key::number("max_overlap")
      .unit("d")
      .default_value(number_text(GuardLimits{}.max_overlap))
      .above(0)
      .at_most(0.5)
      .help(
          "a run stops when any overlap (grain-grain, grain-intruder, grain-wall) exceeds this; a pull "
          "is refused when one impact at its speed would");
}

RunGuard::RunGuard(GuardLimits limits, double energy_start) : limits_(limits), energy_start_(energy_start) {}

double max_wall_overlap(const Particles& p, const Box& box) {
  double worst = 0;
  if (!box.wall) return worst;
  const long n = static_cast<long>(p.size());
#pragma omp parallel for schedule(static) reduction(max : worst)
  for (long i = 0; i < n; ++i)
    if (p.species[i] == Species::Mobile) worst = std::max(worst, p.radius[i] - p.x[i].z());
  return worst;
}

std::string RunGuard::check(const Simulation& sim, double work) {
  const Particles& p = sim.particles();
  const Box& box = sim.box();
  std::ostringstream why;
  why.precision(4);
  const double t = sim.time();
  // One parallel pass (it runs every sample interval): the first body with a non-finite number,
  // and the grains that left the box.
  const long n = static_cast<long>(p.size());
  long first_bad = n, lost = 0, first = n;
#pragma omp parallel for schedule(static) reduction(min : first_bad, first) reduction(+ : lost)
  for (long i = 0; i < n; ++i) {
    if (!(p.x[i].allFinite() && p.v[i].allFinite() && p.omega[i].allFinite() && p.f[i].allFinite() &&
          p.torque[i].allFinite()))
      first_bad = std::min(first_bad, i);
    if (p.species[i] != Species::Mobile) continue;
    const Vec3& x = p.x[i];
    const bool out = x.z() < 0 || x.z() > limits_.z_max || x.x() < -box.lx || x.x() > 2 * box.lx ||
                     x.y() < -box.ly || x.y() > 2 * box.ly;
    if (out) {
      ++lost;
      first = std::min(first, i);
    }
  }
  // Non-finite numbers first: every other check would be meaningless.
  if (first_bad < n) {
    why << "non-finite position, velocity or force of particle " << first_bad << " at t = " << t;
    return why.str();
  }
  grains_lost_ = std::max(grains_lost_, lost);
  if (lost > 0) {
    const Vec3& x = p.x[first];
    why << lost << " grain(s) left the box at t = " << t << ", e.g. grain " << first << " at (" << x.x()
        << ", " << x.y() << ", " << x.z() << "); the box is [0, " << box.lx << ") x [0, " << box.ly
        << ") x [0, " << limits_.z_max << "]";
    return why.str();
  }
  const double overlap = std::max(sim.contacts().max_overlap(p, box), max_wall_overlap(p, box));
  max_overlap_seen_ = std::max(max_overlap_seen_, overlap);
  if (overlap > limits_.max_overlap) {
    why << "overlap " << overlap << " d at t = " << t << " exceeds max_overlap = " << limits_.max_overlap
        << " d: the contacts are too soft (kn = " << sim.contact().kn
        << ") for this speed or height of fall; use a stiffer kn, a slower run, or a larger max_overlap";
    return why.str();
  }
  const double mobile = static_cast<double>(std::max<std::size_t>(1, p.count(Species::Mobile)));
  const double gain = sim.energy().total() - energy_start_ - work;
  if (!std::isfinite(gain) || gain > limits_.energy_gain * mobile) {
    why << "the energy of the grains grew by " << gain / mobile
        << " rho g d^4 per grain more than the work done on them, at t = " << t << " (bound "
        << limits_.energy_gain << "): the run is blowing up; the time step dt = " << sim.dt()
        << " is too large for kn = " << sim.contact().kn << ", or the state was overlapping";
    return why.str();
  }
  return "";
}

}  // namespace granudrag
