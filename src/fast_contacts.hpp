#pragma once
#include <vector>

#include "contact_forces.hpp"
#include "contact_history.hpp"
#include "neighbor_list.hpp"

namespace granudrag {

// The production path. Each grain pair is evaluated once, by the thread that owns its row;
// the partner's share is parked in a per-entry buffer and gathered through the transposed
// list afterwards. No atomics and a fixed summation order: forces are bitwise identical for
// any thread count.
class FastContacts : public ContactForces {
 public:
  explicit FastContacts(double skin) : list_(skin) {}
  bool update_lists(Particles& p, const Box& box) override;
  void accumulate(Particles& p, const Box& box, const ContactParams& c, double dt,
                  bool update_history) override;
  double elastic_energy(const Particles& p, const Box& box, const ContactParams& c) const override;
  int contacts_of(int body) const override;
  const NeighborList& list() const { return list_; }

 private:
  NeighborList list_;
  ContactHistory grain_history_, large_history_;
  std::vector<Vec3> partner_force_, partner_torque_;  // per grain-list entry
  std::vector<Vec3> large_force_, large_torque_;      // per large-list entry
};

}  // namespace granudrag
