#pragma once
// How the contact forces between bodies are found and summed. Two implementations share the
// contact law: VerletContacts (cell grid, Verlet lists, parallel) and BruteForceContacts (every
// pair, serial, obviously correct), which the tests keep as the oracle for the fast path.
#include <algorithm>
#include <cstdint>
#include <vector>

#include "contact/contact_params.hpp"
#include "core/box.hpp"
#include "core/particles.hpp"
#include "core/timer.hpp"

namespace granudrag {

// The history of one touching pair, as stored in checkpoints and bed files: i < j, and the
// spring as seen from i (the relative displacement of i's contact point against j's).
struct PairHistory {
  int i, j;
  Vec3 shear;
};

class ContactLoop {
 public:
  virtual ~ContactLoop() = default;
  // Positions at the last list build, or nullptr for a loop without lists. The integrator
  // measures each body's displacement from them in its drift, so that the rebuild check costs
  // no pass over the bodies of its own.
  virtual const std::vector<Vec3>* build_positions() const { return nullptr; }
  // Called after every position update, with the largest squared displacement of any body from
  // build_positions() (HUGE_VAL when it was not measured: before the first build, or without
  // lists); returns true when it rebuilt its pair lists (positions may then have been wrapped
  // into the box). With `timers`, a rebuild charges the list build to Phase::Neighbor and the
  // carry-over of the springs to Phase::History.
  virtual bool update_lists(Particles& p, const Box& box, Timers* timers, double max_drift_sq) = 0;
  // Whether update_lists() would rebuild, asked by every thread of a team (it changes nothing).
  virtual bool rebuild_due(std::size_t bodies, double max_drift_sq) const = 0;
  // Adds the forces and torques of all body-body contacts to p.f and p.torque, in a parallel
  // region of its own: the three calls below.
  void accumulate(Particles& p, const Box& box, const ContactParams& c, double dt, bool update_history);
  // accumulate() in phases, for a caller that runs them inside its own parallel region
  // (Simulation::step runs a step in one, a fork and a join fewer each pass over the bodies):
  // prepare_accumulate() before the region, accumulate_in_team() by every thread of the team
  // (it ends without a barrier), and once the team has passed a barrier, finish_accumulate() by
  // each thread on bodies first .. last - 1, its own, adding what was held back for them (sums
  // of private arrays, intruder pairs) in a fixed order per body: the bits of the forces do not
  // depend on how the bodies are split between the threads.
  virtual void prepare_accumulate() {}
  virtual void accumulate_in_team(Particles& p, const Box& box, const ContactParams& c, double dt,
                                  bool update_history) = 0;
  virtual void finish_accumulate(Particles& /*p*/, long /*first*/, long /*last*/) {}
  // Energy stored in the normal springs of all touching pairs.
  virtual double elastic_energy(const Particles& p, const Box& box, const ContactParams& c) const = 0;
  // Number of bodies touching particle `body` (an intruder) at the last force evaluation.
  virtual int contacts_of(int body) const = 0;
  // Number of touching body-body pairs at the last force evaluation.
  virtual long contact_count() const = 0;
  // Grains that touched particle `body` (an intruder) at the last force evaluation but not at
  // the one before: the contacts that formed in the last step (contact angle, paper Eq. 6).
  virtual void new_contacts_of(int body, std::vector<int>& grains) const = 0;
  // Grains touching particle `body` (an intruder) at the last force evaluation: the contacts
  // present at an instant (the time-weighted contact angle).
  virtual void touching_contacts_of(int body, std::vector<int>& grains) const = 0;
  // Adds 1 to contacts[k] for every touching pair (k, other): coordination numbers.
  virtual void count_contacts(std::vector<int>& contacts) const = 0;
  // Largest overlap delta among touching pairs, d.
  virtual double max_overlap(const Particles& p, const Box& box) const = 0;
  // Largest overlap among all pairs in reach, touching at the last evaluation or not (a bed
  // just read, before any force evaluation), d.
  virtual double deepest_overlap(const Particles& p, const Box& box) const = 0;
  // Rebuilds the pair lists now (wrapping positions), whether or not they are due.
  virtual void rebuild(Particles& p, const Box& box) = 0;
  // The tangential springs of all touching pairs, and their restoration after a rebuild.
  virtual std::vector<PairHistory> export_history() const = 0;
  virtual void import_history(const std::vector<PairHistory>& history) = 0;

  // The active region (engine/active_region.hpp): per body, 1 when it is held in place this
  // step. A pair of two held bodies is skipped (neither its force nor its spring nor its
  // `touching` changes); every other pair is computed as usual. nullptr (the default): none.
  // The mask is read, not copied; held_changed() is called whenever its contents change.
  void set_held(const std::vector<std::uint8_t>* held) {
    held_ = held;
    held_changed();
  }
  virtual void held_changed() {}
  // Per body, the force from its touching partners held with it, their springs as they are
  // (constant while both stay held); zero for the others. Called when the held set changes.
  // With `load`, also the mean magnitude of those pair forces per body (0 without any).
  virtual void held_pair_forces(const Particles& p, const Box& box, const ContactParams& c,
                                std::vector<Vec3>& force, std::vector<double>* load) const = 0;
  // Sets exposed[i] = 1 for every body with a pair this loop may compute before its next list
  // build: a partner not held like it, or an intruder. A held grain left at 0 has nothing but
  // gravity acting on it (ActiveRegion::classify_quiet). The default marks every body: a loop
  // without lists (the brute-force oracle) steps every held grain, the reference of the fast one.
  virtual void mark_exposed(std::vector<std::uint8_t>& exposed) const {
    std::fill(exposed.begin(), exposed.end(), std::uint8_t{1});
  }

 protected:
  // held_pair_forces' sums, shared by every loop: each held pair's force on both bodies and,
  // with `load`, the mean of their magnitudes once finish() divides by the counts.
  class HeldPairSums {
   public:
    HeldPairSums(std::size_t bodies, std::vector<Vec3>& force, std::vector<double>* load);
    void add(int i, int j, const Vec3& f);
    void finish();

   private:
    std::vector<Vec3>& force_;
    std::vector<double>* load_;
    std::vector<int> count_;
  };
  bool both_held(int i, int j) const { return held_ && (*held_)[i] && (*held_)[j]; }
  const std::vector<std::uint8_t>* held_ = nullptr;
};

}  // namespace granudrag
