#pragma once
// The geometry of a grain pair for the contact law, from the particles' arrays.
#include <cmath>

#include "contact/contact_law.hpp"
#include "core/box.hpp"
#include "core/particles.hpp"

namespace granudrag {

// Geometry of the pair (i, j) if it touches; false otherwise.
inline bool pair_geometry(const Particles& p, const Box& box, int i, int j, ContactGeometry& g) {
  g.del = box.min_image(p.x[i] - p.x[j]);
  const double rsq = g.del.squaredNorm();
  const double radsum = p.radius[i] + p.radius[j];
  if (rsq >= radsum * radsum) return false;
  g.r = std::sqrt(rsq);
  g.contact_distance = radsum;
  g.reff = p.radius[i] * p.radius[j] / radsum;
  g.meff = effective_mass(p.mass[i], p.species[i], p.mass[j], p.species[j]);
  g.rel_velocity = p.v[i] - p.v[j];
  g.spin_sum = p.radius[i] * p.omega[i] + p.radius[j] * p.omega[j];
  return true;
}

}  // namespace granudrag
