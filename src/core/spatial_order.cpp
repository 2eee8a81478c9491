#include "core/spatial_order.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>

namespace granudrag {

namespace {

// Interleaves the low 16 bits of a and b: the Morton code of cell (a, b).
std::uint32_t interleave(std::uint32_t a, std::uint32_t b) {
  auto spread = [](std::uint32_t v) {
    v &= 0xffff;
    v = (v | (v << 8)) & 0x00ff00ff;
    v = (v | (v << 4)) & 0x0f0f0f0f;
    v = (v | (v << 2)) & 0x33333333;
    v = (v | (v << 1)) & 0x55555555;
    return v;
  };
  return spread(a) | (spread(b) << 1);
}

// A layer's thickness, d. A row's partners lie up to a contact's reach ahead of it along the
// sweep, and a layer adds its own thickness to that (the Morton curve ignores the sweep axis
// within it): thin layers keep the two-colour schedule's blocks apart (1 d layers did not, on
// the oracle tests' intruder scene at 2 threads), while a layer still holds enough grains for
// the curve's locality.
constexpr double kLayer = 0.25;

std::uint32_t cell(double c) { return static_cast<std::uint32_t>(std::clamp(std::floor(c), 0.0, 65535.0)); }

}  // namespace

SweepAxis sweep_axis(const Particles& p, const Box& box) {
  double zmin = HUGE_VAL, zmax = -HUGE_VAL;
  for (std::size_t i = 0; i < p.size(); ++i)
    if (p.species[i] != Species::Intruder) {
      zmin = std::min(zmin, p.x[i].z());
      zmax = std::max(zmax, p.x[i].z());
    }
  const double longer = std::max(box.lx, box.ly);
  if (!(zmax - zmin < longer)) return SweepAxis::Z;
  return box.lx >= box.ly ? SweepAxis::X : SweepAxis::Y;
}

std::vector<std::size_t> spatial_order(const Particles& p, const Box& box, SweepAxis axis) {
  if (axis == SweepAxis::Auto) axis = sweep_axis(p, box);
  const std::size_t n = p.size();
  double zmin = HUGE_VAL;
  for (std::size_t i = 0; i < n; ++i)
    if (p.species[i] != Species::Intruder) zmin = std::min(zmin, p.x[i].z());
  std::vector<std::uint64_t> key(n);
  for (std::size_t i = 0; i < n; ++i) {
    if (p.species[i] == Species::Intruder) {
      key[i] = UINT64_MAX;  // last
      continue;
    }
    Vec3 x = p.x[i];
    box.wrap(x);
    const double z = x.z() - zmin;
    std::uint64_t layer = 0;
    std::uint32_t curve = 0;
    switch (axis) {
      case SweepAxis::X:
        layer = cell(x.x() / kLayer);
        curve = interleave(cell(x.y()), cell(z));
        break;
      case SweepAxis::Y:
        layer = cell(x.y() / kLayer);
        curve = interleave(cell(x.x()), cell(z));
        break;
      default:
        layer = cell(z / kLayer);
        curve = interleave(cell(x.x()), cell(x.y()));
        break;
    }
    key[i] = (layer << 32) | curve;
  }
  std::vector<std::size_t> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return key[a] < key[b]; });
  return order;
}

std::vector<std::size_t> inverse_order(const std::vector<std::size_t>& order) {
  std::vector<std::size_t> rank(order.size());
  for (std::size_t k = 0; k < order.size(); ++k) rank[order[k]] = k;
  return rank;
}

Particles reordered(const Particles& p, const std::vector<std::size_t>& order) {
  Particles q;
  q.reserve(order.size());
  for (std::size_t i : order) {
    const std::size_t k = q.add(p.x[i], p.radius[i], p.species[i]);
    q.v[k] = p.v[i];
    q.omega[k] = p.omega[i];
    q.f[k] = p.f[i];
    q.torque[k] = p.torque[i];
    q.mass[k] = p.mass[i];
  }
  return q;
}

}  // namespace granudrag
