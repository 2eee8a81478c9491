#pragma once
// One DEM system and its step loop: velocity Verlet as LAMMPS does it (fix nve/sphere), the
// forces of a step computed from the new positions and the half-step velocities.
#include <memory>
#include <utility>
#include <vector>

#include "contact/contact_loop.hpp"
#include "contact/contact_params.hpp"
#include "contact/wall_contacts.hpp"
#include "core/box.hpp"
#include "core/particles.hpp"
#include "core/timer.hpp"
#include "engine/active_region.hpp"

namespace granudrag {

struct Settings {
  double dt = 0.0;    // 0: derived from the Hertz collision time (default_time_step)
  double skin = 0.2;  // Verlet skin, in grain diameters
  Vec3 gravity{0.0, 0.0, -1.0};
  bool brute_force = false;     // use the O(N^2) oracle instead of the neighbour lists
  ActiveRegionSettings active;  // off unless active.radius > 0
  // A viscous drag -viscous_damping m v, and a torque -viscous_damping I omega, on every mobile
  // grain from time viscous_from on, as LAMMPS fix viscous and fix viscous/sphere (their gamma =
  // viscous_damping m, resp. I): it drains the slow elastic breathing a settling bed keeps for a
  // long time, and the spin of rattlers no contact damps. 0: off (the same step loop, bit for bit).
  double viscous_damping = 0.0;  // sqrt(g/d)
  double viscous_from = 0.0;     // sqrt(d/g)
};

struct Energy {
  double kinetic = 0, rotational = 0, potential = 0, elastic = 0;
  double total() const { return kinetic + rotational + potential + elastic; }
  Energy& operator+=(const Energy& o) {
    kinetic += o.kinetic, rotational += o.rotational, potential += o.potential, elastic += o.elastic;
    return *this;
  }
};

class Simulation {
 public:
  Simulation(Particles particles, Box box, ContactParams contact, Settings settings);

  // Builds the lists and evaluates the forces of the initial state without advancing the
  // tangential springs (LAMMPS' setup). Called by the first step() if not called before.
  void setup();
  void step();
  void run(long steps, bool show_progress = false);

  Particles& particles() { return p_; }
  const Particles& particles() const { return p_; }
  // The bodies thread `thread` of a team of `threads` integrates: first, last (exclusive).
  std::pair<long, long> body_range(int thread, int threads) const;
  const Box& box() const { return box_; }
  const ContactParams& contact() const { return contact_; }
  const Settings& settings() const { return settings_; }
  double dt() const { return dt_; }
  long steps_done() const { return steps_; }
  double time() const { return steps_ * dt_; }
  const Timers& timers() const { return timers_; }
  Timers& timers() { return timers_; }
  const ContactLoop& contacts() const { return *contacts_; }
  // nullptr when the active region is off.
  const ActiveRegion* active_region() const { return region_.get(); }

  // Energy of the mobile grains: kinetic, rotational, gravitational, and elastic (normal
  // springs of all contacts). Conserved without damping and friction.
  Energy energy() const;

  // Checkpointing. A checkpoint is taken right after a forced rebuild, so that a resumed run
  // rebuilds from the very same (wrapped) positions and continues bitwise identically; the
  // forces of the last step are part of the state (the next half-kick uses them).
  void rebuild_lists();
  struct State {
    Particles particles;
    std::vector<PairHistory> pair_history;
    std::vector<Vec3> wall_history;
    long steps = 0;
    ActiveRegion::State region;  // empty when the region is off (or the state is a bed's)
  };
  State state() const;
  void restore(const State& s);  // replaces particles, histories and the step count
  WallContacts& wall() { return wall_; }

 private:
  // The integrator's passes over bodies first .. last - 1, one thread's share of the step.
  // First half-kick and drift; clears the forces for the next evaluation. Returns the largest
  // squared displacement of these bodies since the last list build (HUGE_VAL if not measurable).
  double initial_integrate(long first, long last);
  // By every thread of the team: the contact forces, then its bodies' totals and second kick.
  void forces_and_final_kick(long first, long last);
  void final_integrate(long first, long last);  // add_body_force, then the second half-kick
  void clear_forces();
  void contact_forces(bool update_history);  // body-body and wall contacts, added to f and torque
  // Gravity on a mobile grain; nothing on a frozen one. Inlined: a call per body cost 1 % of a pull.
  [[gnu::always_inline]] inline void add_body_force(long i);
  void lists_rebuilt();  // the wall's candidates and the integrator's split follow the lists
  // The active region's quiet grains (ActiveRegion::classify_quiet) from the lists as they are,
  // and the list of the others.
  void classify_quiet(bool promote);
  // Calls body(i, held) for the bodies first .. last - 1 but the quiet ones, held: whether the
  // region holds body i.
  template <class Body>
  void for_stepped(long first, long last, Body&& body);
  // The integrator's bodies are split into one contiguous range per thread of about equal cost
  // (of the listed bodies' when the region lists them).
  void balance_bodies(int threads);
  bool stepping_listed() const;  // for_stepped visits the region's lists, not every body
  void compute_kicks();
  void ensure_body_split();  // balances if the thread count or the number of bodies changed

  Particles p_;
  Box box_;
  ContactParams contact_;
  Settings settings_;
  double dt_;
  std::unique_ptr<ContactLoop> contacts_;
  std::unique_ptr<ActiveRegion> region_;
  // With the region, the bodies that are not quiet, ascending: those it integrates (awake grains,
  // intruders) and the held ones (whose forces the wake test sums). Two lists, not one: held and
  // awake grains lie mixed in index, and the test which one a body is, mispredicted at every
  // change, cost more than their integration.
  std::vector<int> stepped_moving_, stepped_held_;
  WallContacts wall_;
  std::vector<long> body_split_;         // thread t integrates bodies body_split_[t] .. body_split_[t+1]
  std::vector<double> kick_v_, kick_w_;  // per body: dt / 2m and dt / 2I
  std::vector<double> thread_drift_;     // per thread: the largest squared drift of its bodies
  Timers timers_;
  long steps_ = 0;
  bool ready_ = false;
  bool damping_ = false;  // this step adds the viscous drag
};

// s with its bodies in `order` (order[k]: the body that goes to position k,
// core/spatial_order.hpp): the particles, the per-body arrays of the wall and the active
// region, and the pair springs renamed, each kept in the canonical orientation (i < j, seen
// from i).
Simulation::State reordered(const Simulation::State& s, const std::vector<std::size_t>& order);

}  // namespace granudrag
