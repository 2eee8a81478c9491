#pragma once
// What a settled bed looks like along z: the packing-fraction profile and the free surface.
//
// Surface height (the definition granudrag uses everywhere, stored with each bed): the height
// at which the packing fraction of the grains, in slabs of 0.1 d, falls to half its bulk value.
// The bulk value is the median over the slabs from 2 d above the wall to 4 d below the bed's
// top (the highest slab denser than a tenth of the densest), leaving out slabs cut by the
// intruder. Depth h = surface height - intruder centre height. Half-bulk is the usual Gibbs-like
// choice for a rough surface: it is insensitive to the odd grain rolling on top or in flight.
#include <vector>

#include "core/box.hpp"
#include "core/particles.hpp"

namespace granudrag {

struct BedProfile {
  double slab = 0.1;
  std::vector<double> z;                 // slab centres
  std::vector<double> packing_fraction;  // grains only (the intruder excluded)
  double bulk_packing_fraction = 0;
  double surface_height = 0;
};

// Exact volumes of the spheres' slices in each slab.
BedProfile measure_bed(const Particles& p, const Box& box, double slab = 0.1);

// Volume of the part of a sphere of radius r centred at height zc that lies in [z0, z1].
double sphere_slice_volume(double r, double zc, double z0, double z1);

}  // namespace granudrag
