#pragma once
// The fastest pull a bed allows. An intruder moving at V hits grains at rest at speed V; being
// driven at constant velocity it acts as an infinite mass, so a grain of mass m and radius r
// meets a Hertz spring F = K_n sqrt(R_eff) delta^{3/2}, R_eff = R r / (R + r). Three bounds:
//   overlap     the largest overlap of one undamped impact, (5 m V^2 / (4 K_n sqrt(R_eff)))^{2/5}
//               for the largest grain, must not exceed max_overlap (the bound at which a running
//               pull stops); measured with K_n = 2e4, D = 2, h = 4 d: the largest overlap in the
//               bed is 1.5 (V = 5), 1.2 (V = 10), 1.1 (V = 20), 0.85 (V = 50) times this estimate
//   resolution  the impact lasts t_c = 2.9432 (5 m / (4 K_n sqrt(R_eff)))^{2/5} V^{-1/5} for the
//               smallest grain; dt must resolve it with TimeStepPolicy::steps_per_collision_min
//               steps, as for grain-grain collisions (contact/contact_params.hpp)
//   skin        V dt <= skin / 10: the intruder crosses the half skin that forces a Verlet-list
//               rebuild in no fewer than 5 steps
#include <string>

#include "protocol/pour.hpp"

namespace granudrag {

struct SpeedLimits {
  double overlap = 0, resolution = 0, skin = 0;  // largest V each bound allows
  double fastest() const;
  // The undamped impact overlap at speed V (largest grain), d.
  double impact_overlap(double speed) const;
  // The time step that resolves an impact at speed V.
  double dt_for(double speed) const;

  double kn = 0, reff_large = 0, m_large = 0, reff_small = 0, m_small = 0;
};

SpeedLimits speed_limits(const Bed& bed, double dt, double skin, double max_overlap);

// Throws Error naming 'speed' (and the Froude number) when V breaks a bound: says which, the
// largest speed that works with this bed, and for the time-step bounds the dt to pour with.
void check_pull_speed(double speed, const Bed& bed, double dt, double skin, double max_overlap);

}  // namespace granudrag
