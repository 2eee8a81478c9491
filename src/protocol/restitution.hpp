#pragma once
// The coefficient of restitution of a grain hitting the wall (paper Fig. 2), two ways:
// dropped in the DEM engine itself, and from a direct high-accuracy integration of the
// two-body viscoelastic Hertz equation m x'' = -sqrt(R x)(K_n x + m gamma_n x') (x the
// overlap), which the engine must reproduce.
#include <vector>

#include "contact/contact_params.hpp"

namespace granudrag {

struct Collision {
  double restitution;  // -x'(end) / x'(0)
  double duration;
};

// Classical RK4 with 2e5 steps per collision, the end of contact located by interpolation.
Collision hertz_collision(double kn, double gamman, double meff, double reff, double speed);

// A grain of diameter `diameter` launched at the wall at normal speed `speed` without gravity,
// with the engine's own time step for the contact law; returns v_out / v_in.
double dem_restitution(const ContactParams& c, double speed, double diameter = 1.0);

}  // namespace granudrag
