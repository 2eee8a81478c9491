#pragma once
// Placing an intruder into a settled bed (as LAMMPS `create_atoms single` then `delete_atoms
// overlap`): the grains the intruder's volume would cut are removed, the intruder is held at the
// requested depth below the bed's free surface, and the bed settles again to the kinetic-energy
// threshold. One column poured without an intruder then serves every depth and D of its seed,
// where the paper's protocol pours a bed per intruder (validation: config/validate/placement.yaml).
#include <cmath>
#include <string>
#include <vector>

#include "core/parameter_table.hpp"
#include "protocol/pour.hpp"

namespace granudrag {

// Each field that is a key starts at its default (placement_keys() reads it from here).
struct PlacementSpec {
  double intruder_diameter = 2.0;
  double intruder_x = NAN, intruder_y = NAN;  // NaN: the box's centre
  double depth = NAN;                         // of the intruder centre below the bed's free surface
  double ke_threshold = 1e-7;                 // settled when the kinetic energy per grain is below
  double min_settle_time = 1.0;               // sqrt(d/g): the threshold is not tested before
  double max_settle_time = 20;                // sqrt(d/g): stop settling anyway (recorded)
  double check_interval = 0.5;                // sqrt(d/g) between kinetic-energy checks
  double settle_damping = 0;                  // sqrt(g/d), as the pour's
  // A source bed whose pour ran out of time with its grains' kinetic energy above this many
  // ke_threshold never settled: placing into it would measure its settling, not the intruder's.
  double source_ke_factor = 10;
  double skin = kDefaultSkin;
  double max_overlap = GuardLimits{}.max_overlap;

  void validate() const;  // every field within its key's range (placement_keys())
};

const KeyTable<PlacementSpec>& placement_keys();

// What a placement did, recorded in the bed file's /placement.
struct PlacementRecord {
  std::vector<long> removed;  // indices, in the source bed, of the grains removed
  double source_surface_height = 0;
  double source_kinetic_energy = 0;  // per grain, when the source's pour stopped
  double intruder_z = 0;             // where the intruder was placed (and held)
};

// The source bed with the intruder in place and the grains it cuts removed, before settling:
// histories of the kept pairs and walls carried over, the intruder last. Throws Error naming the
// key for a source with an intruder, an unsettled source, an intruder that does not fit the box,
// or a depth outside the bed (above its surface, or into its frozen base).
Bed placed_column(const Bed& source, const PlacementSpec& spec, PlacementRecord* record);

// Settles a placed column with its intruder held: the placement's settling (progress on stderr).
// The bed returned has its profile, surface and depth measured again.
class Placement {
 public:
  Placement(const Bed& placed, const PlacementSpec& spec);
  void run(bool show_progress);
  const Bed& result() const { return bed_; }
  const Simulation& simulation() const { return sim_; }
  std::string timing_report() const;

 private:
  PlacementSpec spec_;
  Bed bed_;
  Simulation sim_;
  RunGuard guard_;
  double energy_start_ = 0;
  double loop_seconds_ = 0;
  long loop_steps_ = 0;
};

}  // namespace granudrag
