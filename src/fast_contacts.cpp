#include "fast_contacts.hpp"

#include "contact_law.hpp"

namespace granudrag {

namespace {

// Geometry of the pair (i, j) if it touches; false otherwise.
inline bool pair_geometry(const Particles& p, const Box& box, int i, int j, ContactGeometry& g) {
  g.del = box.min_image(p.x[i] - p.x[j]);
  const double rsq = g.del.squaredNorm();
  const double radsum = p.radius[i] + p.radius[j];
  if (rsq >= radsum * radsum) return false;
  g.r = std::sqrt(rsq);
  g.contact_distance = radsum;
  g.reff = p.radius[i] * p.radius[j] / radsum;
  g.meff = effective_mass(p.mass[i], p.kind[i], p.mass[j], p.kind[j]);
  g.rel_velocity = p.v[i] - p.v[j];
  g.spin_sum = p.radius[i] * p.omega[i] + p.radius[j] * p.omega[j];
  return true;
}

}  // namespace

bool FastContacts::update_lists(Particles& p, const Box& box) {
  if (!list_.needs_rebuild(p)) return false;
  list_.build(p, box);
  grain_history_.carry_over(list_.previous_grain_pairs(), list_.grain_pairs());
  large_history_.carry_over(list_.previous_large_pairs(), list_.large_pairs());
  partner_force_.assign(list_.grain_pairs().size(), Vec3::Zero());
  partner_torque_.assign(list_.grain_pairs().size(), Vec3::Zero());
  large_force_.assign(list_.large_pairs().size(), Vec3::Zero());
  large_torque_.assign(list_.large_pairs().size(), Vec3::Zero());
  return true;
}

void FastContacts::accumulate(Particles& p, const Box& box, const ContactParams& c, double dt,
                              bool update_history) {
  const PairList& pairs = list_.grain_pairs();
  const long n = static_cast<long>(p.size());

#pragma omp parallel
  {
#pragma omp for schedule(static)
    for (long i = 0; i < n; ++i) {
      Vec3 fi = Vec3::Zero(), ti = Vec3::Zero();
      for (int e = pairs.begin(i); e < pairs.end(i); ++e) {
        const int j = pairs.partner[e];
        ContactGeometry g;
        if (!pair_geometry(p, box, static_cast<int>(i), j, g)) {
          grain_history_.shear[e].setZero();
          grain_history_.touching[e] = 0;
          partner_force_[e].setZero();
          partner_torque_[e].setZero();
          continue;
        }
        grain_history_.touching[e] = 1;
        const ContactForce cf = hertz_history(c, g, dt, grain_history_.shear[e], update_history);
        fi += cf.force;
        ti -= p.radius[i] * cf.torque;
        partner_force_[e] = -cf.force;
        partner_torque_[e] = -p.radius[j] * cf.torque;
      }
      p.f[i] += fi;
      p.torque[i] += ti;
    }

    const std::vector<int>& t_off = list_.transpose_offset();
    const std::vector<int>& t_entry = list_.transpose_entry();
#pragma omp for schedule(static)
    for (long j = 0; j < n; ++j) {
      Vec3 fj = Vec3::Zero(), tj = Vec3::Zero();
      for (int k = t_off[j]; k < t_off[j + 1]; ++k) {
        fj += partner_force_[t_entry[k]];
        tj += partner_torque_[t_entry[k]];
      }
      p.f[j] += fj;
      p.torque[j] += tj;
    }

    // Intruder pairs: evaluated in parallel into per-entry buffers, summed serially below.
    const PairList& large = list_.large_pairs();
    const std::vector<int>& bodies = list_.large_bodies();
    for (std::size_t b = 0; b < bodies.size(); ++b) {
      const int i = bodies[b];
#pragma omp for schedule(static)
      for (int e = large.begin(b); e < large.end(b); ++e) {
        ContactGeometry g;
        if (!pair_geometry(p, box, i, large.partner[e], g)) {
          large_history_.shear[e].setZero();
          large_history_.touching[e] = 0;
          large_force_[e].setZero();
          large_torque_[e].setZero();
          continue;
        }
        large_history_.touching[e] = 1;
        const ContactForce cf = hertz_history(c, g, dt, large_history_.shear[e], update_history);
        large_force_[e] = cf.force;
        large_torque_[e] = cf.torque;
      }
    }
  }

  const PairList& large = list_.large_pairs();
  const std::vector<int>& bodies = list_.large_bodies();
  for (std::size_t b = 0; b < bodies.size(); ++b) {
    const int i = bodies[b];
    for (int e = large.begin(b); e < large.end(b); ++e) {
      const int j = large.partner[e];
      p.f[i] += large_force_[e];
      p.torque[i] -= p.radius[i] * large_torque_[e];
      p.f[j] -= large_force_[e];
      p.torque[j] -= p.radius[j] * large_torque_[e];
    }
  }
}

double FastContacts::elastic_energy(const Particles& p, const Box& box,
                                    const ContactParams& c) const {
  double energy = 0.0;
  auto add_pair = [&](int i, int j) {
    ContactGeometry g;
    if (pair_geometry(p, box, i, j, g))
      energy += hertz_normal_energy(c.kn, g.reff, g.contact_distance - g.r);
  };
  const PairList& pairs = list_.grain_pairs();
  for (std::size_t i = 0; i < pairs.rows(); ++i)
    for (int e = pairs.begin(i); e < pairs.end(i); ++e) add_pair(static_cast<int>(i), pairs.partner[e]);
  const PairList& large = list_.large_pairs();
  for (std::size_t b = 0; b < large.rows(); ++b)
    for (int e = large.begin(b); e < large.end(b); ++e)
      add_pair(list_.large_bodies()[b], large.partner[e]);
  return energy;
}

int FastContacts::contacts_of(int body) const {
  const PairList& large = list_.large_pairs();
  const std::vector<int>& bodies = list_.large_bodies();
  for (std::size_t b = 0; b < bodies.size(); ++b) {
    if (bodies[b] != body) continue;
    int n = 0;
    for (int e = large.begin(b); e < large.end(b); ++e) n += large_history_.touching[e];
    return n;
  }
  return 0;
}

}  // namespace granudrag
