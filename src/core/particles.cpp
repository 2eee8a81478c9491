#include "core/particles.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace granudrag {

double sphere_mass(double radius) { return 4.0 / 3.0 * M_PI * radius * radius * radius; }

void Particles::reserve(std::size_t n) {
  for (auto* a : {&x, &v, &omega, &f, &torque}) a->reserve(n);
  radius.reserve(n);
  mass.reserve(n);
  species.reserve(n);
}

std::size_t Particles::add(const Vec3& position, double r, Species k) {
  x.push_back(position);
  v.push_back(Vec3::Zero());
  omega.push_back(Vec3::Zero());
  f.push_back(Vec3::Zero());
  torque.push_back(Vec3::Zero());
  radius.push_back(r);
  mass.push_back(sphere_mass(r));
  species.push_back(k);
  return x.size() - 1;
}

std::size_t Particles::freeze_below(double z) {
  std::size_t n = 0;
  for (std::size_t i = 0; i < size(); ++i) {
    if (species[i] == Species::Mobile && x[i].z() < z) {
      species[i] = Species::Frozen;
      v[i].setZero();
      omega[i].setZero();
      ++n;
    }
  }
  return n;
}

std::size_t Particles::count(Species k) const { return std::count(species.begin(), species.end(), k); }

double Particles::min_radius(Species k) const {
  double r = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < size(); ++i)
    if (species[i] == k) r = std::min(r, radius[i]);
  return r;
}

double Particles::max_radius(Species k) const {
  double r = 0.0;
  for (std::size_t i = 0; i < size(); ++i)
    if (species[i] == k) r = std::max(r, radius[i]);
  return r;
}

}  // namespace granudrag
