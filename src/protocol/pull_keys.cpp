// The keys of a pull, declared once: `granudrag pull` reads them from the command line and YAML,
// prints them in --help and --schema, and PullSpec::validate() checks a PullSpec against them.
#include <utility>

#include "core/error.hpp"
#include "protocol/pull.hpp"

namespace granudrag {

const std::vector<ParameterSpec>& pull_keys() {
  static const std::vector<ParameterSpec> keys = {
      Key::number("speed").unit("sqrt(g d)").above(0).help("pulling speed V along +x (default 1)"),
      Key::number("froude").above(0).help("or: the Froude number 2V sqrt(2D/g)/(D+d), paper Eq. 4"),
      Key::number("distance")
          .unit("d")
          .default_value("0")
          .at_least(0)
          .help("travel; 0: one box length (as in the paper); with target_error, the most it may travel"),
      Key::number("target_error")
          .default_value("0")
          .at_least(0)
          .at_most(1)
          .help(
              "stop once the drag's relative standard error is at most this (with >= 10 effective samples), "
              "after min_distance; 0: travel the whole distance"),
      Key::number("min_distance")
          .unit("d")
          .default_value("0")
          .at_least(0)
          .help("travel before target_error may stop the pull"),
      Key::number("sample_interval")
          .unit("sqrt(d/g)")
          .default_value("0.02")
          .above(0)
          .help("forces are averaged over each interval"),
      Key::number("transient")
          .unit("d")
          .default_value("-1")
          .help("travel discarded before averaging; < 0: min(D + d, distance/4)"),
      Key::number("shell").unit("d").default_value("2").above(0).help(
          "Z is measured for grains with centre within D/2 + shell"),
      Key::integer("snapshots")
          .default_value("3")
          .at_least(0)
          .at_most(1000)
          .help("velocity snapshots of the slab through the intruder"),
      Key::number("slab_half_width")
          .unit("d")
          .default_value("0.5")
          .above(0)
          .help("half width of that slab in y"),
      Key::number("active_radius")
          .unit("d")
          .default_value("0")
          .at_least(0)
          .help(
              "active region: grains farther than this from the intruder's centre that stay at rest for "
              "sleep_time fall asleep (held in place, their mutual contacts not computed) until the intruder "
              "comes within it or wake_force wakes them; 0: off (every grain integrated); at least D/2 + 2"),
      Key::number("sleep_distance")
          .unit("d")
          .default_value("0.01")
          .above(0)
          .help("active region: a grain that has moved less than this over sleep_time is at rest (not its "
                "speed: elastic waves keep far grains vibrating at a few percent of V)"),
      Key::number("sleep_time")
          .unit("sqrt(d/g)")
          .default_value("1")
          .at_least(0)
          .help("active region: how long a grain stays at rest before it falls asleep"),
      Key::number("wake_force")
          .unit("m g")
          .default_value("0.5")
          .above(0)
          .help("active region: a sleeping grain wakes when the net force on it, averaged over a check "
                "interval, "
                "has changed by more than this fraction of its weight since it fell asleep"),
  };
  return keys;
}

void PullSpec::validate() const {
  std::vector<ParameterSpec> keys = pull_keys();
  keys.push_back(skin_key());
  keys.push_back(max_overlap_key());
  check_ranges(keys,
               {{"speed", speed},
                {"distance", distance},
                {"target_error", target_error},
                {"min_distance", min_distance},
                {"sample_interval", sample_interval},
                {"transient", transient},
                {"shell", shell},
                {"snapshots", snapshots},
                {"slab_half_width", slab_half_width},
                {"active_radius", active.radius},
                {"sleep_distance", active.sleep_distance},
                {"sleep_time", active.sleep_time},
                {"wake_force", active.wake_force},
                {"skin", skin},
                {"max_overlap", max_overlap}},
               "pull settings");
  // Not a key: `granudrag pull` derives it from checkpoint_interval.
  if (checkpoint_every < 0)
    throw Error("'checkpoint_every' = " + std::to_string(checkpoint_every) +
                " is out of range: it must be >= 0 (steps between checkpoints; 0: none)");
}

}  // namespace granudrag
