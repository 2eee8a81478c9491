#pragma once
// Initial arrangements of grains for benchmarks and tests (the physical pour is `granudrag pour`).
#include <cstdint>

#include "core/box.hpp"
#include "core/particles.hpp"

namespace granudrag {

struct LatticeBed {
  Particles particles;
  Box box;
};

// n grains with diameters uniform in [0.9, 1.1] on an fcc lattice whose nearest-neighbour
// distance is `spacing` (>= 1.1: no initial overlaps; 1.1 gives packing fraction 0.556),
// stacked from the wall up in a square periodic box chosen so that the bed is about half as
// tall as it is wide. Deterministic for a given seed.
LatticeBed fcc_bed(long n, std::uint64_t seed, double spacing = 1.1);

// Gives every mobile grain a random velocity of magnitude `speed` (isotropic direction) and a
// random angular velocity of magnitude `spin`.
void randomize_velocities(Particles& p, double speed, double spin, std::uint64_t seed);

}  // namespace granudrag
