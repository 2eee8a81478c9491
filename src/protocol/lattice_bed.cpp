#include "protocol/lattice_bed.hpp"

#include <cmath>
#include <random>

#include "core/error.hpp"

namespace granudrag {

LatticeBed fcc_bed(long n, std::uint64_t seed, double spacing) {
  if (n < 1) throw Error("number of grains must be >= 1 (got " + std::to_string(n) + ")");
  if (spacing < 1.1) throw Error("fcc spacing must be >= 1.1 so that grains do not overlap");
  const double a = spacing * std::sqrt(2.0);  // cubic cell of the fcc lattice
  // Bed about half as tall as wide: n = 4 k^2 m with m ~ k/2 cells high.
  const int k = std::max(3, static_cast<int>(std::lround(std::cbrt(n / 2.0))));
  LatticeBed bed;
  bed.box.lx = bed.box.ly = k * a;
  bed.box.wall = true;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> diameter(0.9, 1.1);
  const double basis[4][3] = {{0, 0, 0}, {0.5, 0.5, 0}, {0.5, 0, 0.5}, {0, 0.5, 0.5}};
  bed.particles.reserve(n);
  for (int layer = 0; bed.particles.size() < static_cast<std::size_t>(n); ++layer)
    for (int b = 0; b < 4 && bed.particles.size() < static_cast<std::size_t>(n); ++b) {
      for (int ix = 0; ix < k && bed.particles.size() < static_cast<std::size_t>(n); ++ix)
        for (int iy = 0; iy < k && bed.particles.size() < static_cast<std::size_t>(n); ++iy) {
          const Vec3 pos((ix + basis[b][0] + 0.25) * a, (iy + basis[b][1] + 0.25) * a,
                         (layer + basis[b][2]) * a + 0.6);
          bed.particles.add(pos, 0.5 * diameter(rng), Species::Mobile);
        }
    }
  return bed;
}

void randomize_velocities(Particles& p, double speed, double spin, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> gauss(0.0, 1.0);
  auto direction = [&] {
    Vec3 d(gauss(rng), gauss(rng), gauss(rng));
    return Vec3(d / d.norm());
  };
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (p.species[i] != Species::Mobile) continue;
    p.v[i] = speed * direction();
    p.omega[i] = spin * direction();
  }
}

}  // namespace granudrag
