// The keys of a pull, declared once and bound to PullSpec's fields: `granudrag pull` reads them
// from the command line and YAML into a PullSpec, prints them in --help and --schema, and
// PullSpec::validate() checks a PullSpec against them.
#include "core/error.hpp"
#include "protocol/pull.hpp"

namespace granudrag {

const KeyTable<PullSpec>& pull_keys() {
  static const KeyTable<PullSpec> keys = {
      // Speed and Froude number are alternatives: the command reads whichever is given
      // (pull_speed), so neither row has a default and the help states the speed's.
      Key::number("speed")
          .unit("sqrt(g d)")
          .above(0)
          .help("pulling speed V along +x (default " + number_text(PullSpec{}.speed) + ")")
          .field(&PullSpec::speed)
          .read_by_command(),
      Key::number("froude").above(0).help("or: the Froude number 2V sqrt(2D/g)/(D+d), paper Eq. 4"),
      Key::number("distance")
          .unit("d")
          .at_least(0)
          .help("travel; 0: one box length (as in the paper); with target_error, the most it may travel")
          .field(&PullSpec::distance),
      Key::number("target_error")
          .at_least(0)
          .at_most(1)
          .help(
              "stop once the drag's relative standard error is at most this (with >= 10 effective samples), "
              "after min_distance; 0: travel the whole distance")
          .field(&PullSpec::target_error),
      Key::number("min_distance")
          .unit("d")
          .at_least(0)
          .help("travel before target_error may stop the pull")
          .field(&PullSpec::min_distance),
      Key::number("sample_interval")
          .unit("sqrt(d/g)")
          .above(0)
          .help("forces are averaged over each interval")
          .field(&PullSpec::sample_interval),
      Key::number("transient")
          .unit("d")
          .help("travel discarded before averaging; < 0: min(D + d, distance/4)")
          .field(&PullSpec::transient),
      Key::number("shell")
          .unit("d")
          .above(0)
          .help("Z is measured for grains with centre within D/2 + shell")
          .field(&PullSpec::shell),
      Key::integer("snapshots")
          .at_least(0)
          .at_most(1000)
          .help("velocity snapshots of the slab through the intruder")
          .field(&PullSpec::snapshots),
      Key::number("slab_half_width")
          .unit("d")
          .above(0)
          .help("half width of that slab in y")
          .field(&PullSpec::slab_half_width),
      Key::number("active_radius")
          .unit("d")
          .at_least(0)
          .help(
              "active region: grains farther than this from the intruder's centre that stay at rest for "
              "sleep_time fall asleep (held in place, their mutual contacts not computed) until the intruder "
              "comes within it or wake_force wakes them; 0: off (every grain integrated); at least D/2 + 2")
          .field(&PullSpec::active, &ActiveRegionSettings::radius),
      // The radius in intruder diameters: one setting for a sweep over D (the command reads it,
      // pull_active_radius, as it reads froude).
      Key::number("active_diameters")
          .unit("D")
          .at_least(0)
          .help("or: the active region's radius in intruder diameters, active_radius = this D (3 agrees "
                "within errors for D = 1, 2, 4, 6 at mu = 0-0.8, the yield speed to Fr = 10, K_n = 2e4, the "
                "intruder 7 d deep; 5 also 24 d deep and at K_n = 2e5 and 2e6, where 3 leans high: "
                "docs/pour-and-pull.md)"),
      Key::number("sleep_speed")
          .unit("V")
          .above(0)
          .help("active region: a grain that has moved less than this fraction of the intruder's travel over "
                "sleep_time is at rest (relative to V: the grains creeping around a slow intruder must stay "
                "awake, the far field vibrates at 1e-4 d; 0.01 held grains still creeping and read the drag "
                "2-9 % high)")
          .field(&PullSpec::sleep_speed),
      Key::number("sleep_speed_max")
          .unit("sqrt(g d)")
          .above(0)
          .help("active region: the rest test's speed, sleep_speed V, is at most this (a fast pull's wake "
                "still moves at a few hundredths of d per time unit and must not be held)")
          .field(&PullSpec::sleep_speed_max),
      Key::number("sleep_time")
          .unit("sqrt(d/g)")
          .at_least(0)
          .help("active region: how long a grain stays at rest before it falls asleep")
          .field(&PullSpec::active, &ActiveRegionSettings::sleep_time),
      Key::number("wake_force")
          .unit("m g")
          .above(0)
          .help("active region: a sleeping grain wakes when the net force on it, averaged over a check "
                "interval, has changed by more than this fraction of its weight since it fell asleep "
                "(default: 0.5 up to K_n = 2e5, four times more per decade above, 2 at 2e6, where 0.5 woke "
                "grains as often as they slept: the force of a given creep grows as K_n^(2/3); the run "
                "file records the value used)")
          .field(&PullSpec::active, &ActiveRegionSettings::wake_force),
      Key::number("wake_load")
          .unit("contact force")
          .at_least(0)
          .help("active region (experimental): the wake test's threshold is at least this fraction of the "
                "grain's mean contact force with its sleeping partners (deep in a bed they carry tens of "
                "weights, and a stiff bed's elastic ripples change the net force by several without moving "
                "a grain); 0: off, the threshold is wake_force alone")
          .field(&PullSpec::active, &ActiveRegionSettings::wake_load),
      // A coarser step than the pour's: the command sets the bed's dt from the field
      // (pull_time_step), as LAMMPS's timestep after read_restart; the run file records the dt used.
      Key::number("collision_steps")
          .at_least(TimeStepPolicy::steps_per_collision_min)
          .help(
              "the pull's time step as steps per Hertz collision time of two of the bed's smallest grains "
              "at " +
              number_text(TimeStepPolicy::reference_speed) + " sqrt(gd) (a bed's dt is that over " +
              number_text(TimeStepPolicy::steps_per_collision_default) +
              " unless poured with dt): 32 halves a pull's cost; validation: config/validate/time_step.yaml; "
              "unset: the bed's dt")
          .field(&PullSpec::collision_steps),
      // Rows that other commands share (their defaults must be PullSpec's).
      Key(skin_key()).field(&PullSpec::skin),
      Key(max_overlap_key()).field(&PullSpec::max_overlap),
      Key::flag("keep_going")
          .help(
              "on a sanity failure (grains lost, overlap, energy; not NaN) finish the pull and record it as "
              "the run file's /sanity verdict, which the analysis leaves out, instead of stopping")
          .field(&PullSpec::keep_going),
      Key::number("perturbation")
          .unit("sqrt(g d)")
          .at_least(0)
          .help(
              "replica: add this to the x velocity of the mobile grain nearest the intruder before the first "
              "step, so the pull parts from the same pull through the same bed by chaos alone (e.g. 1e-9); "
              "beside a comparison it measures how far two pulls through one bed differ for no reason; 0: "
              "off")
          .field(&PullSpec::perturbation),
      Key::flag("fresh_start")
          .help("drop the bed's contact histories and recompute forces first, as LAMMPS does after read_data")
          .field(&PullSpec::fresh_start),
  };
  return keys;
}

void PullSpec::validate() const {
  pull_keys().check(*this, "pull settings");
  // Not a key: `granudrag pull` derives it from checkpoint_interval.
  if (checkpoint_every < 0)
    throw Error("'checkpoint_every' = " + std::to_string(checkpoint_every) +
                " is out of range: it must be >= 0 (steps between checkpoints; 0: none)");
}

}  // namespace granudrag
