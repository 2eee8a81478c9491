#pragma once
// Pulling the intruder (paper Sec. II): it moves at constant V along +x at fixed y and z, across
// the periodic boundary, and the force on it and the state of the grains around it are
// recorded. The step loop is the engine's; this adds sampling, statistics and checkpoints.
#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include "engine/run_guard.hpp"
#include "engine/simulation.hpp"
#include "protocol/coordination_shells.hpp"
#include "protocol/observables.hpp"
#include "protocol/pour.hpp"

namespace granudrag {

// Each field that is a key starts at its default (pull_keys() reads it from here).
struct PullSpec {
  double speed = 1.0;   // V, sqrt(g d)
  double distance = 0;  // travel, d; 0: one box length (as in the paper); with
                        // target_error, the most it may travel
  // Sequential stopping: end the pull once the drag's relative standard error is at most this
  // (and the error estimate has converged), after min_distance of travel; 0: run the distance.
  double target_error = 0;
  double min_distance = 0;        // d
  double sample_interval = 0.02;  // sqrt(d/g): forces are averaged over each interval
  double transient = -1;          // travel discarded before averaging, d; <0: min(D + d, distance/4)
  double shell = 2.0;             // Z is measured for grains whose centre is within R + shell
  int snapshots = 3;              // velocity-field snapshots of the slab through the intruder
  double slab_half_width = 0.5;   // |y - Y| < this for the snapshots, d
  long checkpoint_every = 0;      // steps between checkpoints (rounded to whole samples); 0: none
  long dump_every = 0;            // steps between frames (the first at step 0); 0: none
  double skin = kDefaultSkin;
  // Drop the bed's contact histories and recompute the forces before the first step, as a
  // LAMMPS run starting from a data file does: for like-for-like comparisons.
  bool fresh_start = false;
  double max_overlap = GuardLimits{}.max_overlap;  // d: refused above (one impact at V), stopped above
  // On a sanity failure other than a non-finite number: finish the pull and record the failure
  // as the run's verdict instead of stopping.
  bool keep_going = false;
  // A replica: before the first step, this is added to the x velocity of the mobile grain
  // nearest the intruder (replica_grain()). The same pull through the same bed, parted from it
  // by chaos alone: pulled beside a comparison through one bed, it measures how far two pulls
  // differ for no reason (analysis/validation.py). 0: off.
  double perturbation = 0;      // sqrt(g d)
  ActiveRegionSettings active;  // the active region (engine/active_region.hpp); off by default
  // The region's rest test, relative to V: a grain is at rest when it moves slower than this
  // fraction of V over sleep_time (the pull sets active.sleep_distance from it). 0.003, not the
  // 0.01 of before: that held grains still creeping at 0.3-1 % of V, and the drag read 2-9 % high
  // where much of the bed slept (pooled over the validations +1.6 +- 0.8 %, at 0.003 +0.6 +- 0.9 %:
  // config/validate/active_region_40_*.yaml, docs/pour-and-pull.md).
  double sleep_speed = 0.003;
  // ... and at most this speed, d per sqrt(d/g): relative to V alone, a fast pull held grains of
  // its wake still moving at a few hundredths of a grain diameter per time unit, and the drag
  // rose (config/validate/active_region_40_fast.yaml).
  double sleep_speed_max = 0.014;
  double collision_steps = NAN;  // steps per Hertz collision time (pull_time_step); NaN: the bed's dt

  // Every field within its key's range (pull_keys()); throws Error naming the key.
  void validate() const;
};

// The keys of a pull (speed or Froude number, travel, sampling, the active region, the run's
// limits), each bound to its PullSpec field and declared once: `granudrag pull` builds its
// command line, --help and --schema from them and reads them into a PullSpec, and
// PullSpec::validate() checks against them. The defaults are PullSpec's.
const KeyTable<PullSpec>& pull_keys();

struct Snapshot {
  double time = 0;
  std::vector<double> dx, dz, vx, vz;  // grains in the slab, in the intruder's frame
};

// Everything a pull accumulates; with the simulation state it is the whole checkpoint.
struct PullRecord {
  long samples_per_interval = 1;
  long total_steps = 0;
  // One entry per sample interval: time at its end, mean force on the intruder over it,
  // mean intruder coordination number over it.
  std::vector<double> time, fx, fy, fz, contacts;
  // With the active region: grains asleep at the end of each interval (empty without it).
  std::vector<double> sleeping;
  // Contact angles (paper Eq. 6) at formation, after the transient.
  double theta_sum = 0;
  long theta_count = 0;
  std::vector<long> theta_histogram = std::vector<long>(36, 0);  // 5-degree bins on [0, pi]
  // theta_sum and theta_count at the end of each sample interval: the series theta's error is
  // estimated from (ratio_error). NaN for the intervals of a checkpoint written before it.
  std::vector<double> theta_sum_series, theta_count_series;
  // The angles of the contacts present at the end of each sample interval (every interval, the
  // transient too), their sum and count: theta weighted by how long each contact lasts, where
  // theta_sum counts each contact once, as it forms. NaN for a checkpoint written before it.
  std::vector<double> theta_present_sum, theta_present_count;
  // Bulk coordination number of grains in the shell, after the transient.
  std::vector<long> z_histogram = std::vector<long>(16, 0);  // Z = 0 .. 15 (15: >= 15)
  CoordinationShells shells;  // Z in nested shells of every width, the same samples
  std::vector<Snapshot> snapshots;
  double work = 0;         // done by the intruder on the grains
  double max_overlap = 0;  // largest overlap seen at a sample, d
  long grains_lost = 0;    // most grains out of the box at a sample
  std::string verdict;     // the first sanity failure (keep_going), "" while clean
  // Why the pull ended: "distance" (travelled it all) or "target_error" (the drag's error met
  // the target first; total_steps is then the step it stopped at); "" while it runs.
  std::string stop_reason;
  double energy_start = 0;  // of the mobile grains
  long frames = 0;          // frames handed to on_frame so far (--dump_interval)
  // Running sums over the current interval.
  Vec3 force_sum = Vec3::Zero();
  double contact_sum = 0;
};

// Whether the sequential-stopping rule checks the error after n samples past the transient:
// 16 times per doubling of n (n a multiple of 2^k/16, 2^k <= n < 2^(k+1)), from 16 samples
// on, so that the checks cost O(n) over a pull and fall on the same samples in a resumed run.
bool stopping_check_due(long n);

struct PullResult {
  // The drag: -<F_x> after the transient (positive when it resists the motion along +x), and
  // its standard error (mean_error, protocol/observables.hpp) with its effective degrees of
  // freedom and whether the error converged. The record keeps the raw force components.
  double drag = NAN, drag_error = NAN, drag_dof = NAN;
  bool drag_plateau = false;
  double transient_distance = 0;
  long transient_samples = 0;
  std::vector<double> cumulative_drag;  // running mean of -F_x over all samples (Fig. 4)
  // The drag and its error from the first samples after the transient, growing to all of them
  // (prefix_errors); travel per sample: samples_per_interval * dt * speed.
  std::vector<PrefixError> drag_convergence;
  double travel_per_sample = NAN;
  double coordination = NAN;                               // n: mean number of grains touching the intruder
  double coordination_error = NAN;                         // its standard error (mean_error, as the drag's)
  double theta = NAN, theta_error = NAN, theta_dof = NAN;  // theta's error: ratio_error
  // theta over the contacts present at each sample after the transient (time-weighted), and
  // its error (ratio_error of the samples' sums and counts).
  double theta_present = NAN, theta_present_error = NAN, theta_present_dof = NAN;
  double bulk_coordination = NAN;            // Z
  std::vector<double> z_distribution;        // P(Z)
  double kappa = NAN;                        // (Z/n)(D+d)^2/(2 sqrt(3) d^2), paper Eq. 8
  std::vector<double> shell_z, shell_kappa;  // Z and kappa within R + CoordinationShells::widths
  double froude = NAN;                       // 2V sqrt(2D/g)/(D+d), paper Eq. 4
};

double froude_number(double speed, double diameter);

class Pull {
 public:
  Pull(const Bed& bed, const PullSpec& spec);
  // Continues from a checkpoint: the bed (box, parameters), the state and the record.
  Pull(const Bed& bed, const PullSpec& spec, const Simulation::State& state, PullRecord record);

  // Runs to the end. on_checkpoint is called every spec.checkpoint_every steps, right after
  // the forced rebuild that makes a resumed run bitwise identical. Throws Error when the run
  // guard (engine/run_guard.hpp) finds a failure at the end of a sample interval, before a
  // checkpoint could save it; with spec.keep_going only a non-finite number stops it.
  // on_frame is called at step 0 and every spec.dump_every steps after, before a checkpoint
  // due at the same step, and counted in record().frames.
  void run(bool show_progress, const std::function<void(const Pull&)>& on_checkpoint = {},
           const std::function<void(const Pull&)>& on_frame = {});

  PullResult result() const;
  const PullRecord& record() const { return record_; }
  // The simulation steps the bed's bodies in a spatial order (core/spatial_order.hpp), taken
  // once from the bed: body k of simulation() is body order()[k] of bed(). Its state and the
  // checkpoints are in that order; the frames and the snapshots are in the bed's.
  const Simulation& simulation() const { return sim_; }
  const std::vector<std::size_t>& order() const { return order_; }
  int intruder() const { return intruder_; }  // in simulation()'s order
  // The grain a replica perturbs (spec.perturbation), in simulation()'s order: the mobile grain
  // whose centre is nearest the intruder's in the bed, so that the perturbation acts at once.
  int replica_grain() const;
  // The simulation's bodies in the bed's order (for frames).
  Particles particles_in_bed_order() const;
  Simulation::State state() const { return sim_.state(); }
  const Bed& bed() const { return bed_; }
  const PullSpec& spec() const { return spec_; }
  bool finished() const { return sim_.steps_done() >= record_.total_steps; }
  // Sanity report printed at the end of every run (CoMD style).
  std::string sanity_report(double wall_seconds) const;
  // "timing: loop ... s ..., particle-steps/s; integration ... s ..." for the last run(): the
  // step loop alone and its split by phase (core/timer.hpp), one line; then a line
  // "timing: second half ..." for the last half of its steps, which shows the steady cost of a
  // pull whose bed fell asleep in its first part (the active region).
  std::string timing_report() const;
  double loop_seconds() const { return loop_seconds_; }
  long loop_steps() const { return loop_steps_; }
  // "clean", or the first sanity failure of a keep_going pull.
  std::string verdict() const { return record_.verdict.empty() ? "clean" : record_.verdict; }

 private:
  void after_step();
  void end_of_interval();
  bool target_met() const;
  long samples_in_transient() const;
  double transient_distance() const;
  MeanError theta_error(double t0) const;
  double contact_angle(int grain) const;  // theta of a grain touching the intruder, rad
  int grains_lost() const;

  Bed bed_;
  PullSpec spec_;
  std::vector<std::size_t> order_, rank_;  // simulation body k is bed body order_[k]; rank_: inverse
  int intruder_ = -1;
  Simulation sim_;
  PullRecord record_;
  RunGuard guard_;
  long planned_steps_ = 0;  // for the whole distance: the transient and snapshots are set by it
  std::vector<int> scratch_;
  std::vector<int> counts_;
  double loop_seconds_ = 0, half_seconds_ = 0;
  long loop_steps_ = 0, half_steps_ = 0;
};

}  // namespace granudrag
