#pragma once
// The active region (`granudrag pull --active_radius`): away from the intruder a gravity-settled
// bed sits in static equilibrium, yet a plain step loop recomputes every one of its contacts.
// Grains farther than the radius from every intruder that have stayed slow for a dwell time fall
// asleep: they are held in place (not integrated, velocity and spin zero), and a contact between
// two held bodies is neither computed nor changed (its tangential spring is kept as it was, as
// for a grain at rest). A contact between a held and an awake body is computed as usual, so the
// awake grains feel the sleeping bed as a boundary that pushes back exactly as it did.
//
// "At rest" is measured by displacement, not speed: while an intruder is pulled, elastic waves
// keep every grain of a stiff bed vibrating at a few percent of V, far from the intruder too,
// with amplitudes of 1e-4 d: speeds say all grains move, displacements say they do not. The
// pull sets the distance relative to the intruder's travel (its key sleep_speed), since a slow
// pull's failure zone creeps at a few percent of V and must not be held.
//
// A sleeping grain wakes when it comes within the radius of an intruder (the region follows it
// through the periodic box), or when the net force on it, averaged over a check interval, has
// moved from its value in the first interval after it fell asleep by more than wake_force times
// its weight: stress carried out of the region along a force chain wakes the grains it loads.
// With wake_load set, the threshold is the larger of that and wake_load times the grain's mean
// contact force from its held partners: deep in a bed a grain's contacts carry tens of times its
// weight, and the elastic ripples of a stiff bed change its net force by more than a few weights
// without moving anything (the churn that kept a 2e6 bed's region from saving CPU). Counting held
// partners only errs towards waking: an awake partner's load is left out of the scale.
// The net force is the sum over its awake partners (computed every step anyway, and summed over
// the interval), gravity, and its contacts with other held bodies, which are constant while both
// are held and evaluated once whenever the held set changes. Frozen base grains count as held.
//
// A held grain none of whose list partners is awake (nor the wall, nor an intruder) is quiet:
// nothing acts on it but gravity and its held partners, so no step touches it (its force stays
// m g, as the full path computes it). Most of a settled bed far from the intruder is quiet, and
// the integrator's passes over it were most of what a sleeping grain still cost. A grain turns
// quiet only at a check where the held set changed, and stops being quiet at any list build
// that gives it an awake partner, or when it wakes.
//
// Decisions are taken every check interval (a fraction of sleep_time, short enough that the
// intruder moves at most half a grain diameter) in one parallel pass, so the bookkeeping costs
// an addition per held grain and step, and the held set changes only then. Off (radius 0),
// nothing here runs and the step loop is bitwise the one without it.
#include <cmath>
#include <cstdint>
#include <vector>

#include "core/box.hpp"
#include "core/particles.hpp"

namespace granudrag {

// The defaults are the pull keys' (protocol/pull_keys.cpp; a test keeps them so).
struct ActiveRegionSettings {
  double radius = 0;             // d, from the intruder's centre; 0: off
  double sleep_distance = 0.01;  // d: moved less than this over sleep_time counts as at rest
                                 // (a pull sets it: min(sleep_speed V, sleep_speed_max)
                                 // sleep_time)
  double sleep_time = 1.0;       // sqrt(d/g): at rest for this long before falling asleep
  double wake_force = NAN;       // fraction of the grain's weight m g; NaN: unset, the pull
                                 // takes default_wake_force(K_n)
  double wake_load = 0;          // fraction of the grain's mean contact force with its held
                                 // partners; the wake test takes the larger threshold; 0: off
  double check_interval = 0.25;  // sqrt(d/g) between decisions (the pull derives it)
  bool skip_quiet = true;        // false: every held grain is stepped (the reference for tests)
  bool enabled() const { return radius > 0; }
};

// The wake test's threshold when a pull leaves it unset: 0.5 up to K_n = 2e5, four times more per
// decade of K_n above (2 at 2e6, 8 at 2e7). The force that a neighbour's creep of a given size puts
// on a held grain grows with the contacts' stiffness (as K_n^(2/3) for Hertz at a given load, 4.6x
// per decade), so a threshold fixed in units of the weight wakes a stiff bed as fast as it sleeps:
// at 2e6, 0.5 saved no CPU. Measured: 0.5 agrees at 2e4 and 2e5, 2 at 2e6
// (config/validate/active_region_30_stiff*.yaml); four per decade joins them, a little more
// sensitive than Hertz's scaling, and 8 at 2e7 agreed too, with as much of the bed asleep as in
// the soft beds (active_region_30_stiffer.yaml, Fr = 1).
double default_wake_force(double kn);

class ActiveRegion {
 public:
  // Everything a resumed run needs to continue bitwise (part of a checkpoint).
  struct State {
    std::vector<std::uint8_t> held;           // per body: 1 asleep (or frozen), 0 integrated
    std::vector<std::int32_t> at_rest;        // per body: consecutive checks found at rest
    std::vector<Vec3> anchor;                 // per awake grain: where its rest began
    std::vector<Vec3> force_sum;              // per held grain: its force from awake partners and
                                              // gravity, summed over the current interval
    std::vector<Vec3> held_force;             // per held grain: from its held partners (constant)
    std::vector<double> held_load;            // per held grain: the mean magnitude of those
                                              // contact forces (only with wake_load)
    std::vector<Vec3> reference;              // per held grain: its mean net force after it fell asleep
    std::vector<std::uint8_t> reference_due;  // per held grain: take it at the next check
    std::vector<std::uint8_t> quiet;          // per body: kQuiet, kTurningQuiet or 0
    std::int64_t interval_steps = 0;          // steps summed into force_sum
    std::int64_t wake_ups = 0, sleeps = 0;
  };

  ActiveRegion(const ActiveRegionSettings& settings, double dt, const Particles& p);

  // Steps between checks.
  long check_steps() const { return check_steps_; }
  // Per body: 1 when held in place this step; the contact loop skips pairs of two.
  const std::vector<std::uint8_t>& held() const { return s_.held; }
  // Called by the integrator for each held grain it steps, once its force of the step is
  // complete: a grain turning quiet has now been stepped the once that leaves its force m g.
  void add_force(long i, const Vec3& f) {
    s_.force_sum[i] += f;
    if (s_.quiet[i] == kTurningQuiet) s_.quiet[i] = kQuiet;
  }
  // After the forces and the second half-kick of step `step` (1-based): at a check, puts grains
  // to sleep and wakes them. Returns true when the held set changed: the caller then re-sorts
  // the contact loop and hands the held partners' forces to set_held_forces().
  bool after_step(Particles& p, const Box& box, long step, const Vec3& gravity);
  std::vector<Vec3>& held_forces() { return s_.held_force; }
  // Where the caller puts the held partners' mean contact force per body, or null without
  // wake_load.
  std::vector<double>* held_loads() { return settings_.wake_load > 0 ? &s_.held_load : nullptr; }
  // Per body: kQuiet when quiet (held, no awake partner): the integrator skips it.
  static constexpr std::uint8_t kQuiet = 1, kTurningQuiet = 2;
  const std::vector<std::uint8_t>& quiet() const { return s_.quiet; }
  // `exposed`: per body, 1 when a list partner of it is not held like it (or it may touch the
  // wall or an intruder). Quiet grains that are exposed stop being quiet (their force sum
  // catches up with the steps they were not stepped, their force and torque are cleared);
  // with `promote` (only at a check, after the held set changed), held grains that are not
  // exposed turn quiet after one more step, whose forces leave them m g and no torque, what
  // the full path gives them at every step from then on.
  void classify_quiet(Particles& p, const std::vector<std::uint8_t>& exposed, bool promote,
                      const Vec3& gravity);

  long sleeping() const { return sleeping_; }  // mobile grains asleep now
  std::int64_t wake_ups() const { return s_.wake_ups; }
  const ActiveRegionSettings& settings() const { return settings_; }
  const State& state() const { return s_; }
  void restore(const State& s, const Particles& p);

 private:
  // The smallest distance from x to an intruder's centre through the periodic box.
  double distance_to_intruders(const Particles& p, const Box& box, const Vec3& x) const;

  ActiveRegionSettings settings_;
  double dt_;
  long check_steps_ = 1;
  std::int32_t dwell_checks_ = 1;  // checks at rest before falling asleep
  std::vector<int> intruders_;
  State s_;
  long sleeping_ = 0;
};

}  // namespace granudrag
