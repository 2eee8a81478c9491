#include "contact/brute_force_contacts.hpp"

#include "contact/contact_law.hpp"

namespace granudrag {

namespace {

// The pair's geometry if it touches, written out here rather than shared with the fast path
// (contact/pair_geometry.hpp), so that the oracle stays an independent computation.
bool touching(const Particles& p, const Box& box, int i, int j, ContactGeometry& g) {
  const Vec3 del = box.min_image(p.x[i] - p.x[j]);
  const double radsum = p.radius[i] + p.radius[j];
  const double r = del.norm();
  if (r >= radsum) return false;
  g.del = del;
  g.r = r;
  g.contact_distance = radsum;
  g.reff = p.radius[i] * p.radius[j] / radsum;
  g.meff = effective_mass(p.mass[i], p.species[i], p.mass[j], p.species[j]);
  g.rel_velocity = p.v[i] - p.v[j];
  g.spin_sum = p.radius[i] * p.omega[i] + p.radius[j] * p.omega[j];
  return true;
}

}  // namespace

bool BruteForceContacts::update_lists(Particles&, const Box&, Timers*, double) { return false; }

void BruteForceContacts::accumulate_in_team(Particles& p, const Box& box, const ContactParams& c, double dt,
                                            bool update_history) {
#pragma omp single nowait
  accumulate_serial(p, box, c, dt, update_history);
}

void BruteForceContacts::accumulate_serial(Particles& p, const Box& box, const ContactParams& c, double dt,
                                           bool update_history) {
  const int n = static_cast<int>(p.size());
  formed_.clear();
  for (int i = 0; i < n; ++i) {
    for (int j = i + 1; j < n; ++j) {
      if (p.species[i] == Species::Frozen && p.species[j] == Species::Frozen) continue;
      if (both_held(i, j)) continue;  // its spring, if it touches, stays as it was
      ContactGeometry g;
      if (!touching(p, box, i, j, g)) {
        history_.erase({i, j});
        continue;
      }
      const auto [slot, formed] = history_.try_emplace({i, j}, Vec3::Zero());
      if (formed) formed_.push_back({i, j});
      Vec3& shear = slot->second;
      const PairForce cf = hertz_history(c, g, dt, shear, update_history);
      p.f[i] += cf.force;
      p.f[j] -= cf.force;
      p.torque[i] -= p.radius[i] * cf.torque;
      p.torque[j] -= p.radius[j] * cf.torque;
    }
  }
}

double BruteForceContacts::elastic_energy(const Particles& p, const Box& box, const ContactParams& c) const {
  double energy = 0.0;
  const int n = static_cast<int>(p.size());
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j) {
      if (p.species[i] == Species::Frozen && p.species[j] == Species::Frozen) continue;
      const double radsum = p.radius[i] + p.radius[j];
      const double r = box.min_image(p.x[i] - p.x[j]).norm();
      if (r < radsum) energy += hertz_normal_energy(c.kn, p.radius[i] * p.radius[j] / radsum, radsum - r);
    }
  return energy;
}

int BruteForceContacts::contacts_of(int body) const {
  int n = 0;
  for (const auto& entry : history_)
    if (entry.first.first == body || entry.first.second == body) ++n;
  return n;
}

void BruteForceContacts::new_contacts_of(int body, std::vector<int>& grains) const {
  grains.clear();
  for (const auto& [i, j] : formed_)
    if (i == body || j == body) grains.push_back(i == body ? j : i);
}

void BruteForceContacts::touching_contacts_of(int body, std::vector<int>& grains) const {
  grains.clear();
  for (const auto& entry : history_) {
    const auto [i, j] = entry.first;
    if (i == body || j == body) grains.push_back(i == body ? j : i);
  }
}

void BruteForceContacts::count_contacts(std::vector<int>& contacts) const {
  for (const auto& entry : history_) {
    ++contacts[entry.first.first];
    ++contacts[entry.first.second];
  }
}

std::vector<PairHistory> BruteForceContacts::export_history() const {
  std::vector<PairHistory> out;
  for (const auto& [key, shear] : history_) out.push_back({key.first, key.second, shear});
  return out;
}

void BruteForceContacts::import_history(const std::vector<PairHistory>& history) {
  history_.clear();
  for (const PairHistory& h : history) history_[{h.i, h.j}] = h.shear;
}

void BruteForceContacts::held_pair_forces(const Particles& p, const Box& box, const ContactParams& c,
                                          std::vector<Vec3>& force, std::vector<double>* load) const {
  HeldPairSums sums(p.size(), force, load);
  for (const auto& [key, stored] : history_) {
    const auto [i, j] = key;
    if (!both_held(i, j)) continue;
    ContactGeometry g;
    if (!touching(p, box, i, j, g)) continue;
    Vec3 shear = stored;
    sums.add(i, j, hertz_history(c, g, 0.0, shear, false).force);
  }
  sums.finish();
}

double BruteForceContacts::max_overlap(const Particles& p, const Box& box) const {
  double worst = 0;
  for (const auto& entry : history_) {
    const int i = entry.first.first, j = entry.first.second;
    worst = std::max(worst, p.radius[i] + p.radius[j] - box.min_image(p.x[i] - p.x[j]).norm());
  }
  return worst;
}

double BruteForceContacts::deepest_overlap(const Particles& p, const Box& box) const {
  double worst = 0;
  const int n = static_cast<int>(p.size());
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j) {
      if (p.species[i] == Species::Frozen && p.species[j] == Species::Frozen) continue;
      worst = std::max(worst, p.radius[i] + p.radius[j] - box.min_image(p.x[i] - p.x[j]).norm());
    }
  return worst;
}

long BruteForceContacts::contact_count() const { return static_cast<long>(history_.size()); }

}  // namespace granudrag
