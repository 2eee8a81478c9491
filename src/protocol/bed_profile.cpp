#include "protocol/bed_profile.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

#include "core/error.hpp"

namespace granudrag {

double sphere_slice_volume(double r, double zc, double z0, double z1) {
  const double a = std::clamp(z0 - zc, -r, r), b = std::clamp(z1 - zc, -r, r);
  // integral of pi (r^2 - u^2) du from a to b
  auto prim = [r](double u) { return M_PI * (r * r * u - u * u * u / 3.0); };
  return b > a ? prim(b) - prim(a) : 0.0;
}

BedProfile measure_bed(const Particles& p, const Box& box, double slab) {
  BedProfile out;
  out.slab = slab;
  double ztop = 0;
  for (std::size_t i = 0; i < p.size(); ++i)
    if (p.species[i] != Species::Intruder) ztop = std::max(ztop, p.x[i].z() + p.radius[i]);
  const int n = static_cast<int>(std::ceil(ztop / slab)) + 1;
  std::vector<double> volume(n, 0.0);
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (p.species[i] == Species::Intruder) continue;
    const double r = p.radius[i], zc = p.x[i].z();
    const int k0 = std::max(0, static_cast<int>(std::floor((zc - r) / slab)));
    const int k1 = std::min(n - 1, static_cast<int>(std::floor((zc + r) / slab)));
    for (int k = k0; k <= k1; ++k) volume[k] += sphere_slice_volume(r, zc, k * slab, (k + 1) * slab);
  }
  const double slab_volume = box.lx * box.ly * slab;
  out.z.resize(n);
  out.packing_fraction.resize(n);
  for (int k = 0; k < n; ++k) {
    out.z[k] = (k + 0.5) * slab;
    out.packing_fraction[k] = volume[k] / slab_volume;
  }
  // The bed's top from the profile, not from the highest grain, so that a grain in flight does
  // not stretch the bulk window: the highest slab above a tenth of the densest.
  const double densest = *std::max_element(out.packing_fraction.begin(), out.packing_fraction.end());
  int top = n - 1;
  while (top > 0 && out.packing_fraction[top] < 0.1 * densest) --top;
  const double bed_top = out.z[top];
  // Slabs cut by an intruder read low (its volume is not counted): they stay out of the bulk.
  std::vector<std::pair<double, double>> intruders;
  for (std::size_t i = 0; i < p.size(); ++i)
    if (p.species[i] == Species::Intruder) intruders.push_back({p.x[i].z(), p.radius[i]});
  std::vector<double> bulk;
  for (int k = 0; k < n; ++k) {
    if (out.z[k] <= 2.0 || out.z[k] >= bed_top - 4.0) continue;
    bool cut = false;
    for (const auto& [zc, r] : intruders) cut |= std::abs(out.z[k] - zc) < r + 0.5 * slab;
    if (!cut) bulk.push_back(out.packing_fraction[k]);
  }
  if (bulk.size() < 5)
    throw Error(
        "bed is too shallow to measure its surface: it needs at least 6.5 d of grains clear of the "
        "intruder (top at " +
        std::to_string(bed_top) + " d)");
  std::nth_element(bulk.begin(), bulk.begin() + bulk.size() / 2, bulk.end());
  out.bulk_packing_fraction = bulk[bulk.size() / 2];
  const double half = 0.5 * out.bulk_packing_fraction;
  // Highest crossing of the half-bulk level at or below the top, interpolated between slabs.
  bool found = false;
  for (int k = std::min(n - 1, top + 1); k > 0 && !found; --k) {
    if (out.packing_fraction[k - 1] >= half && out.packing_fraction[k] < half) {
      const double f0 = out.packing_fraction[k - 1], f1 = out.packing_fraction[k];
      out.surface_height = out.z[k - 1] + slab * (f0 - half) / (f0 - f1);
      found = true;
    }
  }
  if (!found) throw Error("no free surface found: the packing fraction never falls to half its bulk value");
  return out;
}

}  // namespace granudrag
