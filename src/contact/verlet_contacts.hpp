#pragma once
#include <memory>
#include <vector>

#include "contact/contact_batch.hpp"
#include "contact/contact_history.hpp"
#include "contact/contact_loop.hpp"
#include "contact/neighbor_list.hpp"

namespace granudrag {

// The production path. Each grain pair is evaluated once (Newton's third law), by the thread
// that owns its row; rows are split into one contiguous block per thread of about equal cost
// (list entries, touching pairs weighted as the contact law costs), re-balanced at each rebuild. Thread 0
// adds into the particles' forces directly, as a serial code would; the other threads add into private copies
// that are summed in thread order afterwards. No atomics, and a fixed summation order for a given thread
// count: runs are bitwise reproducible for that count. (A per-pair buffer gathered in fixed order would make
// them independent of the thread count too, but doubled the memory traffic and the cost.)
class VerletContacts : public ContactLoop {
 public:
  explicit VerletContacts(double skin) : list_(skin), simd_(best_simd_level()) {}
  bool update_lists(Particles& p, const Box& box, Timers* timers) override;
  void accumulate(Particles& p, const Box& box, const ContactParams& c, double dt,
                  bool update_history) override;
  double elastic_energy(const Particles& p, const Box& box, const ContactParams& c) const override;
  int contacts_of(int body) const override;
  long contact_count() const override;
  double max_overlap(const Particles& p, const Box& box) const override;
  void new_contacts_of(int body, std::vector<int>& grains) const override;
  void count_contacts(std::vector<int>& contacts) const override;
  void rebuild(Particles& p, const Box& box) override;
  std::vector<PairHistory> export_history() const override;
  void import_history(const std::vector<PairHistory>& history) override;
  const NeighborList& list() const { return list_; }

 private:
  NeighborList list_;
  SimdLevel simd_;  // chosen once, outside any parallel region: a bad GRANUDRAG_SIMD fails here
  ContactHistory grain_history_, intruder_history_;
  void balance_rows(int threads);
  void after_build();
  // Evaluates the batch's touching pairs and adds their forces into f, tq (this thread's arrays).
  [[gnu::noinline]] void evaluate_batch(const Particles& p, const ContactParams& c, double dt,
                                        bool update_history, ContactBatch& b, Vec3* f, Vec3* tq);

  std::vector<std::vector<Vec3>> thread_force_, thread_torque_;  // threads 1.., per particle
  std::vector<std::unique_ptr<ContactBatch>> batches_;           // one per thread
  std::vector<long> row_split_;                         // thread t owns rows row_split_[t] .. row_split_[t+1]
  std::vector<Vec3> intruder_force_, intruder_torque_;  // per intruder-list entry
  std::vector<std::uint8_t> intruder_new_;              // per intruder-list entry: touched first now
};

}  // namespace granudrag
