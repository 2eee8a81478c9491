#pragma once
#include <array>
#include <memory>
#include <vector>

#include "contact/contact_batch.hpp"
#include "contact/contact_history.hpp"
#include "contact/contact_loop.hpp"
#include "contact/neighbor_list.hpp"

namespace granudrag {

// Whether blocks of rows split[b] .. split[b+1] can run in two colours (the even blocks
// together, then the odd ones): no two blocks of one colour write the same body, a row's own
// or a partner's. Conservative: each block's writes are taken as two ranges of bodies.
bool colour_blocks_apart(const PairList& pairs, const std::vector<long>& split);

// The bodies rows i0 .. i1 - 1 write, their own and their partners j > i (rows sorted): those
// short of `limit` lie in i0 .. near_end, the others (rows of a periodic sweep reaching across
// its boundary, or anywhere in a bed in another order) in far_first .. far_last (-1: none).
struct WriteReach {
  long near_end, far_first, far_last;
};
WriteReach write_reach(const PairList& pairs, long i0, long i1, long limit);

// The production path. Each grain pair is evaluated once (Newton's third law), by the thread
// that owns its row; rows are split into two contiguous blocks per thread of about equal cost
// (list entries, touching pairs weighted as the contact law costs), re-balanced at each rebuild.
// When no two blocks of one colour write the same body (bodies ordered by a sweep in space, as
// a pour leaves them and a pull puts them: core/spatial_order.hpp), the even blocks run
// together, then the odd ones, and every thread adds straight into the particles' forces.
// Otherwise thread 0 adds into them directly, and the other threads into private copies summed
// in thread order afterwards, each cleared and summed over the bodies its rows can write only
// (its rows and their reach ahead, and any excursions): bodies in a sweep's order at more
// threads than the colours allow (a 40 d bed at 16) would otherwise clear and sum about N/2
// entries per thread and step, traffic that grows with both. No atomics, and a fixed
// summation order for a given thread count: runs are bitwise reproducible for that count; one
// thread gives the serial order. (A per-pair buffer gathered in fixed order would make them
// independent of the thread count too, but doubled the memory traffic and the cost.)
class VerletContacts : public ContactLoop {
 public:
  explicit VerletContacts(double skin) : list_(skin), simd_(best_simd_level()) {}
  const std::vector<Vec3>* build_positions() const override { return &list_.build_positions(); }
  bool update_lists(Particles& p, const Box& box, Timers* timers, double max_drift_sq) override;
  bool rebuild_due(std::size_t bodies, double max_drift_sq) const override {
    return list_.rebuild_due(bodies, max_drift_sq);
  }
  void prepare_accumulate() override;
  void accumulate_in_team(Particles& p, const Box& box, const ContactParams& c, double dt,
                          bool update_history) override;
  void finish_accumulate(Particles& p, long first, long last) override;
  double elastic_energy(const Particles& p, const Box& box, const ContactParams& c) const override;
  int contacts_of(int body) const override;
  long contact_count() const override;
  double max_overlap(const Particles& p, const Box& box) const override;
  double deepest_overlap(const Particles& p, const Box& box) const override;
  void new_contacts_of(int body, std::vector<int>& grains) const override;
  void touching_contacts_of(int body, std::vector<int>& grains) const override;
  void count_contacts(std::vector<int>& contacts) const override;
  void rebuild(Particles& p, const Box& box) override;
  std::vector<PairHistory> export_history() const override;
  void import_history(const std::vector<PairHistory>& history) override;
  void held_pair_forces(const Particles& p, const Box& box, const ContactParams& c, std::vector<Vec3>& force,
                        std::vector<double>* load) const override;
  void held_changed() override;
  void mark_exposed(std::vector<std::uint8_t>& exposed) const override;
  const NeighborList& list() const { return list_; }
  // Whether the last balance allows the two-colour schedule (no private force arrays).
  bool colored() const { return colored_; }
  // Without it: the bodies threads 1.. clear and sum in their private arrays at each step.
  long private_span() const;

 private:
  NeighborList list_;
  SimdLevel simd_;  // chosen once, outside any parallel region: a bad GRANUDRAG_SIMD fails here
  ContactHistory grain_history_, intruder_history_;
  void balance_rows(int threads);
  // Whether a team of nt threads runs the two colours: the team the rows were balanced for.
  bool two_colours(int nt) const { return colored_ && nt == planned_threads_; }
  void after_build();
  double largest_overlap(const Particles& p, const Box& box, bool touching_only) const;
  // With bodies held (the active region): per row, what the scan computes (RowMode).
  void classify_rows();
  enum RowMode : std::uint8_t { kSkip = 0, kAll = 1, kAwakePartners = 2 };
  std::vector<std::uint8_t> row_mode_;  // empty: every row kAll
  std::vector<int> scanned_rows_;       // with row_mode_: the rows not kSkip, ascending
  // Per scanned row k, awake_entries_[awake_start_[k] .. awake_start_[k + 1]]: the list entries
  // of a kAwakePartners row whose partner is awake (none for a kAll row).
  std::vector<int> awake_start_, awake_entries_;
  // The rows whose pairs the step computes, k = 0 .. checked_rows() - 1: every row, or with
  // bodies held those not kSkip.
  long checked_rows() const {
    return static_cast<long>(row_mode_.empty() ? list_.grain_pairs().rows() : scanned_rows_.size());
  }
  long checked_row(long k) const { return row_mode_.empty() ? k : scanned_rows_[k]; }
  // Calls visit(i, e) for the list entries e of checked row k whose pairs the step computes (not
  // both held), in order: every entry of row i, or of a held row its awake partners'.
  template <class Visit>
  void for_computed_entries(long k, Visit&& visit) const {
    const long i = checked_row(k);
    if (row_mode_.empty() || row_mode_[i] == kAll) {
      for (int e = list_.grain_pairs().begin(i); e < list_.grain_pairs().end(i); ++e) visit(i, e);
    } else {
      for (int m = awake_start_[k]; m < awake_start_[k + 1]; ++m) visit(i, awake_entries_[m]);
    }
  }
  // The held pairs' part of the checks that run every sample interval (energy, largest overlap,
  // coordination numbers). A pair of two held bodies keeps its spring, its `touching` and its
  // geometry while both stay held, so its part is taken once after each change of the held set
  // or of the lists, and the checks scan only the pairs the step computes: in a mostly quiet
  // bed those passes over every pair had become a large part of a step's cost.
  struct HeldPairs {
    bool counted = false, overlapped = false, energized = false;  // which parts are current
    double energy = 0, overlap = 0;
    std::vector<int> contacts;  // per body: its touching held pairs
  };
  mutable HeldPairs held_pairs_;
  void forget_held_pairs() { held_pairs_.counted = held_pairs_.overlapped = held_pairs_.energized = false; }
  const std::vector<int>& held_pair_contacts() const;
  double held_pairs_overlap(const Particles& p, const Box& box) const;
  double held_pairs_energy(const Particles& p, const Box& box, const ContactParams& c) const;
  template <class Visit>
  void for_held_touching_pairs(Visit&& visit) const;  // visit(i, j) for each such pair
  // Scans rows i0 .. i1 for touching pairs and adds their forces into f, tq.
  void scan_rows(const Particles& p, const Box& box, const ContactParams& c, double dt, bool update_history,
                 long i0, long i1, ContactBatch& b, Vec3* f, Vec3* tq);
  // Evaluates the batch's touching pairs and adds their forces into f, tq (this thread's arrays).
  [[gnu::noinline]] void evaluate_batch(const Particles& p, const ContactParams& c, double dt,
                                        bool update_history, ContactBatch& b, Vec3* f, Vec3* tq);

  std::vector<std::vector<Vec3>> thread_force_, thread_torque_;  // threads 1.., per particle
  // Without the colours, for the team the rows were balanced for: per thread, the two ranges of
  // bodies [first, last) its rows write, which are all of its private arrays that are used.
  struct BodyRange {
    long first = 0, last = 0;
  };
  std::vector<std::array<BodyRange, 2>> private_reach_;
  // Thread t of a team of nt: its private ranges (of n bodies).
  std::array<BodyRange, 2> private_ranges(int t, int nt, long n) const;
  std::vector<std::unique_ptr<ContactBatch>> batches_;  // one per thread
  std::vector<long> row_split_;  // block b is rows row_split_[b] .. row_split_[b+1]; thread t has 2t, 2t+1
  bool colored_ = false;         // blocks of one colour never write the same body
  int planned_threads_ = 1;      // the team prepare_accumulate() made ready (omp_get_max_threads())
  std::vector<Vec3> intruder_force_, intruder_torque_;  // per intruder-list entry
  std::vector<std::uint8_t> intruder_new_;              // per intruder-list entry: touched first now
};

}  // namespace granudrag
