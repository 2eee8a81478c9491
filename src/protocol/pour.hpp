#pragma once
// Pouring a bed (paper Sec. II): an intruder held fixed, grains of diameter U[0.9, 1.1] d placed at
// random non-overlapping positions in a loose column above the wall, falling and settling under
// gravity until the kinetic energy is negligible or a time limit is reached; then the grains
// below 0.6 d are frozen into the rough base and the free surface is measured.
#include <cmath>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "contact/contact_loop.hpp"
#include "contact/contact_params.hpp"
#include "core/parameter_table.hpp"
#include "engine/run_guard.hpp"
#include "engine/simulation.hpp"
#include "protocol/bed_profile.hpp"

namespace granudrag {

// The Verlet skin of pours and pulls when none is given, d.
inline constexpr double kDefaultSkin = 0.2;

// Each field that is a key starts at its default (pour_keys() reads it from here).
struct PourSpec {
  double lx = 20, ly = 20;
  long grains = 4000;
  double intruder_diameter = 2.0;  // 0: no intruder
  double intruder_x = 10, intruder_y = 10;
  double depth = NAN;       // requested depth h below the free surface, or ...
  double intruder_z = NAN;  // ... the intruder centre's height (exactly one of the two)
  // Packing fraction assumed to place the intruder at the requested depth before the bed
  // exists; NaN: bulk_packing_estimate(mu), measured.
  double packing_estimate = NAN;
  double fill_fraction = 0.30;  // of the loose column the grains start in
  ContactParams contact;
  double dt = NAN;  // NaN: from the Hertz collision time (default_time_step), as without --dt
  double skin = kDefaultSkin;
  double ke_threshold = 1e-7;    // mean kinetic energy per grain, rho g d^4
  double max_settle_time = 100;  // sqrt(d/g)
  double check_interval = 0.5;   // sqrt(d/g) between kinetic-energy checks
  double settle_damping = 0;     // sqrt(g/d): viscous drag rate once the column has fallen; 0: off
  double base_height = 0.6;      // grains below are frozen into the rough base
  std::uint64_t seed = 1;
  double max_overlap = GuardLimits{}.max_overlap;  // d: the pour stops when an overlap exceeds it
  // Run controls, not keys: kinetic-energy checks between checkpoints and between frames (the
  // first at step 0); 0: none.
  long checkpoint_every = 0;
  long dump_every = 0;

  // Every field within its key's range (pour_keys()), and what no single range says: the intruder
  // inside the box, exactly one of depth and intruder_z, not too many grains for the box, the
  // contact law. Throws Error naming the key and the allowed range.
  void validate() const;
};

// The keys of a pour, one row per PourSpec field (name, unit, range, meaning) bound to it, declared
// once: `granudrag pour` builds its command line, --help and --schema from them and reads them
// into a PourSpec, and PourSpec::validate() checks against them. The defaults are PourSpec's.
const KeyTable<PourSpec>& pour_keys();
// The Verlet skin of pours and pulls.
ParameterSpec skin_key();

struct Bed {
  Simulation::State state;  // particles (intruder last), contact and wall histories
  Box box;
  ContactParams contact;
  double dt = 0;
  int intruder = -1;  // index, or -1
  BedProfile profile;
  double surface_height = 0;
  double depth = NAN;  // surface height - intruder centre height
  double requested_depth = NAN;
  std::string stop_reason;    // "threshold" or "max_time"
  double kinetic_energy = 0;  // per grain, when the pour stopped
  double settle_time = 0;
  std::string sanity;  // the end-of-run report: grains lost, overlaps, energy, throughput
};

// Placement alone (tested on its own): grains at random non-overlapping positions in the
// column [0, lx) x [0, ly) x [0, z_top] at the spec's fill fraction, around the intruder.
Particles place_grains(const PourSpec& spec, double intruder_z, double* column_top);

// Bulk packing fraction of a poured bed against friction, measured with this pour (1500 grains,
// 10 d x 10 d, K_n = 2e4, D = 2): 0.657 at mu = 0 down to 0.598 at mu = 0.9; interpolated
// linearly in mu, constant beyond the table. Frictionless beds pack ~10 % denser, so one fixed
// estimate put their intruders ~1.6 d too shallow.
double bulk_packing_estimate(double mu);

// Where the free surface (half the bulk packing) lies relative to the top of a column holding
// the grains at bulk packing: lower, by the looser layers at the wall and at the top (measured:
// -0.25 to -0.39 d over mu = 0...0.9 in the beds above).
constexpr double kSurfaceOffset = -0.35;

// The intruder height for the requested depth, from the estimated packing fraction.
double intruder_height_for_depth(const PourSpec& spec);

// Everything a pour carries from one kinetic-energy check to the next besides the simulation
// state; with that state (taken right after a forced list rebuild) it is the whole checkpoint.
struct PourRecord {
  double energy_start = 0;    // of the grains after setup, for the run guard
  double max_overlap = 0;     // largest overlap seen at a check, d
  long grains_lost = 0;       // most grains out of the box at a check
  long frames = 0;            // frames handed to on_frame so far (dump_every)
  double kinetic_energy = 0;  // per grain at the last check
  // Why the pour ended: "threshold" (settled) or "max_time"; "" while it runs.
  std::string stop_reason;
};

class Pour {
 public:
  // Places the grains in the loose column around the intruder and sets the forces up. Throws
  // Error naming the key when the spec is invalid or the grains do not fit.
  explicit Pour(const PourSpec& spec);
  // Continues from a checkpoint of a pour with the same spec: its state and record.
  Pour(const PourSpec& spec, const Simulation::State& state, PourRecord record);

  // Runs until the grains have settled or max_settle_time; then freezes the base and measures
  // the bed (result()). on_checkpoint is called every spec.checkpoint_every kinetic-energy checks,
  // right after the forced rebuild that makes a resumed run bitwise identical (same thread count).
  // Throws Error when the run guard (engine/run_guard.hpp) finds a failure at a check, before a
  // checkpoint could save it. on_frame is called at step 0 and every spec.dump_every checks
  // after, before a checkpoint due at the same check, and counted in record().frames. The
  // progress line counts steps to max_settle_time, the most a pour runs: a bed that settles
  // first ends sooner than its ETA.
  void run(bool show_progress, const std::function<void(const Pour&)>& on_checkpoint = {},
           const std::function<void(const Pour&)>& on_frame = {});

  // The settled bed, once finished(); its sanity is sanity_report(loop_seconds()).
  const Bed& result() const { return bed_; }
  const PourRecord& record() const { return record_; }
  const Simulation& simulation() const { return sim_; }
  Simulation::State state() const { return sim_.state(); }
  const PourSpec& spec() const { return spec_; }
  bool finished() const { return !record_.stop_reason.empty(); }
  // Sanity report of the run (the pull's format): grains lost, largest overlap, the grains'
  // energy and its dissipation, throughput. Taken before the base is frozen.
  std::string sanity_report(double wall_seconds) const;
  // The step loop alone and its split by phase for the last run(), one line (as the pull's).
  std::string timing_report() const;
  double loop_seconds() const { return loop_seconds_; }
  long loop_steps() const { return loop_steps_; }

 private:
  struct Column;  // the grains placed around the intruder, before anything moves
  static Column loose_column(const PourSpec& spec);  // validates the spec first
  Pour(const PourSpec& spec, Column column, const Simulation::State* resume);
  void finish();

  PourSpec spec_;
  Simulation sim_;
  PourRecord record_;
  RunGuard guard_;
  Bed bed_;
  double column_top_ = 0;
  long chunk_ = 1;      // steps per kinetic-energy check
  long max_steps_ = 0;  // the step of the last check max_settle_time allows
  double min_settle_time_ = 0;
  // The grains when the loop ended, before the base was frozen: lost, energy.
  long end_lost_ = 0;
  double end_energy_ = 0;
  double loop_seconds_ = 0;
  long loop_steps_ = 0;
};

// Pours a bed in one go: Pour(spec).run(show_progress), its result with the sanity report.
Bed pour(const PourSpec& spec, bool show_progress);

}  // namespace granudrag
