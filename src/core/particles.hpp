#pragma once
// All bodies of a simulation in structure-of-arrays form: one array per property, indexed
// by the particle's position in the store. Grains and the intruder live side by side; their
// species decides how they are integrated and which contact path finds their pairs.
#include <cstdint>
#include <vector>

#include "core/vec3.hpp"

namespace granudrag {

enum class Species : std::uint8_t {
  Mobile = 0,    // a grain integrated by velocity Verlet
  Frozen = 1,    // a grain of the rough base: never moves, takes the mobile partner's m_eff
  Intruder = 2,  // moves at a prescribed velocity, does not rotate
};

struct Particles {
  std::vector<Vec3> x, v, omega, f, torque;
  std::vector<double> radius, mass;
  std::vector<Species> species;

  std::size_t size() const { return x.size(); }
  // Adds a sphere of density 1 (mass in units of rho*d^3), at rest; returns its index.
  std::size_t add(const Vec3& position, double radius, Species species);
  void reserve(std::size_t n);

  bool rotates(std::size_t i) const { return species[i] == Species::Mobile; }
  double inertia(std::size_t i) const { return 0.4 * mass[i] * radius[i] * radius[i]; }
  // Freezes every mobile grain whose centre lies below z (the paper's rough base: 0.6 d).
  std::size_t freeze_below(double z);
  std::size_t count(Species k) const;
  double min_radius(Species k) const;
  double max_radius(Species k) const;
};

double sphere_mass(double radius);

}  // namespace granudrag
