#pragma once
#include <map>
#include <utility>
#include <vector>

#include "contact/contact_loop.hpp"
#include "core/vec3.hpp"

namespace granudrag {

// The oracle: every pair i < j is tested for contact at every step, serially, with the
// histories in an ordered map keyed by the pair. O(N^2) and slow on purpose; no lists, no
// cells, no skin, no buffers: nothing the fast path could get wrong in the same way.
class BruteForceContacts : public ContactLoop {
 public:
  bool update_lists(Particles& p, const Box& box, Timers* timers, double max_drift_sq) override;
  bool rebuild_due(std::size_t, double) const override { return false; }
  // One thread of the team runs the serial loop; the others go on to the barrier.
  void accumulate_in_team(Particles& p, const Box& box, const ContactParams& c, double dt,
                          bool update_history) override;
  double elastic_energy(const Particles& p, const Box& box, const ContactParams& c) const override;
  int contacts_of(int body) const override;
  long contact_count() const override;
  double max_overlap(const Particles& p, const Box& box) const override;
  double deepest_overlap(const Particles& p, const Box& box) const override;
  void new_contacts_of(int body, std::vector<int>& grains) const override;
  void touching_contacts_of(int body, std::vector<int>& grains) const override;
  void count_contacts(std::vector<int>& contacts) const override;
  void rebuild(Particles&, const Box&) override {}
  std::vector<PairHistory> export_history() const override;
  void import_history(const std::vector<PairHistory>& history) override;
  void held_pair_forces(const Particles& p, const Box& box, const ContactParams& c, std::vector<Vec3>& force,
                        std::vector<double>* load) const override;

 private:
  void accumulate_serial(Particles& p, const Box& box, const ContactParams& c, double dt,
                         bool update_history);
  std::map<std::pair<int, int>, Vec3> history_;
  std::vector<std::pair<int, int>> formed_;  // pairs that began touching in the last step
};

}  // namespace granudrag
