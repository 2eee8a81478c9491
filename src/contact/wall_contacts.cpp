#include "contact/wall_contacts.hpp"

#include <algorithm>

#include "contact/contact_law.hpp"
#include "core/ordered_sum.hpp"

namespace granudrag {

void WallContacts::select(const Particles& p, double skin) {
  // Sized here too, so that the first evaluation keeps the selection (see accumulate).
  if (shear_.size() != p.size()) shear_.resize(p.size(), Vec3::Zero());
  near_.clear();
  for (std::size_t i = 0; i < p.size(); ++i)
    if (p.species[i] == Species::Mobile && p.x[i].z() < p.radius[i] + skin)
      near_.push_back(static_cast<int>(i));
  selected_ = true;
}

void WallContacts::prepare(const Particles& p) {
  if (shear_.size() != p.size()) {
    shear_.resize(p.size(), Vec3::Zero());
    selected_ = false;
  }
}

void WallContacts::accumulate(Particles& p, const ContactParams& c, double dt, bool update_history) {
  prepare(p);
  // Grains that were not selected stay out of reach, and their springs at zero, until the
  // next selection: a whole pass over the bodies each step would cost more than the contacts.
  const long n = selected_ ? static_cast<long>(near_.size()) : static_cast<long>(p.size());
#pragma omp parallel for schedule(static) if (n > 4096)
  for (long k = 0; k < n; ++k) evaluate(p, selected_ ? near_[k] : k, c, dt, update_history);
}

void WallContacts::accumulate_range(Particles& p, const ContactParams& c, double dt, bool update_history,
                                    long first, long last) {
  if (!selected_) {
    for (long i = first; i < last; ++i) evaluate(p, i, c, dt, update_history);
    return;
  }
  // near_ is in index order (select).
  for (auto k = std::lower_bound(near_.begin(), near_.end(), first); k != near_.end() && *k < last; ++k)
    evaluate(p, *k, c, dt, update_history);
}

void WallContacts::evaluate(Particles& p, long i, const ContactParams& c, double dt, bool update_history) {
  const double z = p.x[i].z();
  if (p.species[i] != Species::Mobile || z >= p.radius[i]) {
    shear_[i].setZero();
    return;
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

double WallContacts::elastic_energy(const Particles& p, const ContactParams& c) const {
  return ordered_sum<double>(static_cast<long>(p.size()), [&](long i) {
    const double z = p.x[i].z();
    return p.species[i] == Species::Mobile && z < p.radius[i]
               ? hertz_normal_energy(c.kn, p.radius[i], p.radius[i] - z)
               : 0.0;
  });
}

void WallContacts::mark_near(std::vector<std::uint8_t>& exposed) const {
  if (!selected_) {
    std::fill(exposed.begin(), exposed.end(), std::uint8_t{1});
    return;
  }
  for (int i : near_) exposed[i] = 1;
}

}  // namespace granudrag
