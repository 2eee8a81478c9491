#include "bed_profile.hpp"

#include <algorithm>
#include <cmath>

#include "error.hpp"

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
    if (p.kind[i] != Kind::Intruder) ztop = std::max(ztop, p.x[i].z() + p.radius[i]);
  const int n = static_cast<int>(std::ceil(ztop / slab)) + 1;
  std::vector<double> volume(n, 0.0);
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (p.kind[i] == Kind::Intruder) continue;
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
  std::vector<double> bulk;
  for (int k = 0; k < n; ++k)
    if (out.z[k] > 2.0 && out.z[k] < ztop - 4.0) bulk.push_back(out.packing_fraction[k]);
  if (bulk.size() < 5)
    throw Error("bed is too shallow to measure its surface: it needs at least 6.5 d of grains (top at " +
                std::to_string(ztop) + " d)");
  std::nth_element(bulk.begin(), bulk.begin() + bulk.size() / 2, bulk.end());
  out.bulk_packing_fraction = bulk[bulk.size() / 2];
  const double half = 0.5 * out.bulk_packing_fraction;
  // Highest crossing of the half-bulk level, interpolated between slab centres.
  for (int k = n - 1; k > 0; --k) {
    if (out.packing_fraction[k - 1] >= half && out.packing_fraction[k] < half) {
      const double f0 = out.packing_fraction[k - 1], f1 = out.packing_fraction[k];
      out.surface_height = out.z[k - 1] + slab * (f0 - half) / (f0 - f1);
      break;
    }
  }
  return out;
}

}  // namespace granudrag
