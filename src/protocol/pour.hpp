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
  double dt = 0;  // 0: from the Hertz collision time
  double skin = kDefaultSkin;
  double ke_threshold = 1e-7;    // mean kinetic energy per grain, rho g d^4
  double max_settle_time = 100;  // sqrt(d/g)
  double check_interval = 0.5;   // sqrt(d/g) between kinetic-energy checks
  double base_height = 0.6;      // grains below are frozen into the rough base
  std::uint64_t seed = 1;
  double max_overlap = GuardLimits{}.max_overlap;  // d: the pour stops when an overlap exceeds it

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

// Where a pour stands between two kinetic-energy checks: enough to continue it bit for bit.
struct PourState {
  Simulation::State state;  // taken right after a forced list rebuild
  double energy_start = 0;  // of the grains after setup, for the run guard
  double max_overlap_seen = 0;
  long grains_lost = 0;
  double dt = 0;    // the pour's time step (recorded, not restored)
  long frames = 0;  // frames handed to PourCheckpoints::frame so far
};

// Periodic checkpoints of a pour. Every `every` kinetic-energy checks (0: none) the lists are
// rebuilt and `save` is called with the state; a pour resumed from that state with the same
// spec and `every` continues bitwise identically to one never interrupted (same thread count).
struct PourCheckpoints {
  long every = 0;
  std::function<void(const PourState&)> save;
  const PourState* resume_from = nullptr;
  // Frames (--dump_interval): `frame` is called at step 0 and every `frame_every` checks after,
  // before a checkpoint due at the same check, and counted in PourState::frames.
  long frame_every = 0;
  std::function<void(const Simulation&)> frame;
};

// Throws Error, naming the failure (engine/run_guard.hpp), when the pour runs away.
Bed pour(const PourSpec& spec, bool show_progress, const PourCheckpoints& checkpoints = {});

}  // namespace granudrag
