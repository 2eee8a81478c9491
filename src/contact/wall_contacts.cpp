#include "contact/wall_contacts.hpp"

#include "contact/contact_law.hpp"

namespace granudrag {

void WallContacts::accumulate(Particles& p, const ContactParams& c, double dt, bool update_history) {
  if (shear_.size() != p.size()) shear_.resize(p.size(), Vec3::Zero());
  const long n = static_cast<long>(p.size());
#pragma omp parallel for schedule(static)
  for (long i = 0; i < n; ++i) {
    const double z = p.x[i].z();
    if (p.species[i] != Species::Mobile || z >= p.radius[i]) {
      shear_[i].setZero();
      continue;
    }
    ContactGeometry g;
    g.del = Vec3(0.0, 0.0, z);
    g.r = z;
    g.contact_distance = p.radius[i];
    g.reff = p.radius[i];
    g.meff = p.mass[i];
    g.rel_velocity = p.v[i];
    g.spin_sum = p.radius[i] * p.omega[i];
    const PairForce cf = hertz_history(c, g, dt, shear_[i], update_history);
    p.f[i] += cf.force;
    p.torque[i] -= p.radius[i] * cf.torque;
  }
}

double WallContacts::elastic_energy(const Particles& p, const ContactParams& c) const {
  double energy = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const double z = p.x[i].z();
    if (p.species[i] == Species::Mobile && z < p.radius[i])
      energy += hertz_normal_energy(c.kn, p.radius[i], p.radius[i] - z);
  }
  return energy;
}

}  // namespace granudrag
