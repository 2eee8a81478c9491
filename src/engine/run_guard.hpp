#pragma once
// Runaway checks for a running simulation: a run stops (or is flagged) when a number is not
// finite, grains leave the box, an overlap exceeds its bound, or the energy of the grains grows
// by more than the work done on them. Called by the protocols every sample interval (pull) or
// kinetic-energy check (pour), never per step: one pass over the grains and two over the
// contacts (largest overlap, elastic energy), which the protocols computed there anyway.
//
// The criteria, all in the units of docs/engine.md (d, rho g d^4):
//   non-finite    a position, velocity, angular velocity, force or torque is NaN or inf
//   grain lost    a mobile grain's centre is below the wall (z < 0), above z_max, or more than
//                 one box length outside the periodic box in x or y (positions are wrapped at
//                 every list rebuild, so this only happens after a jump of a box length)
//   overlap       the largest grain-grain, grain-intruder or grain-wall overlap > max_overlap
//   energy        E - E_start - W > energy_gain * (mobile grains), E the grains' kinetic,
//                 rotational, gravitational and elastic energy, W the work done on them by the
//                 intruder: a dissipative system driven by W cannot gain energy; a time step
//                 too large for the stiffness makes it grow without bound
#include <cmath>
#include <string>
#include <vector>

#include "core/parameter_spec.hpp"
#include "engine/simulation.hpp"

namespace granudrag {

struct GuardLimits {
  double max_overlap = 0.1;  // d
  double z_max = HUGE_VAL;   // d: a grain above this has left the box
  double energy_gain = 1.0;  // rho g d^4 per mobile grain
};

// The key `max_overlap` of pours and pulls.
ParameterSpec max_overlap_key();

class RunGuard {
 public:
  RunGuard(GuardLimits limits, double energy_start);

  // Checks the state; returns "" when sane, else the reason (one line naming the grain, the
  // time and the bound). `work`: done on the grains by the intruder since energy_start.
  std::string check(const Simulation& sim, double work);

  // What was seen over all checks so far.
  double max_overlap_seen() const { return max_overlap_seen_; }
  long grains_lost() const { return grains_lost_; }
  const GuardLimits& limits() const { return limits_; }
  double energy_start() const { return energy_start_; }
  // Restores what a resumed run had seen (from its checkpoint).
  void restore(double max_overlap_seen, long grains_lost) {
    max_overlap_seen_ = max_overlap_seen;
    grains_lost_ = grains_lost;
  }

 private:
  GuardLimits limits_;
  double energy_start_;
  double max_overlap_seen_ = 0;
  long grains_lost_ = 0;
};

// Largest overlap of a mobile grain with the wall at z = 0 (0 without wall or contact).
double max_wall_overlap(const Particles& p, const Box& box);

}  // namespace granudrag
