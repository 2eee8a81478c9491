// The keys of a pour, declared once: `granudrag pour` reads them from the command line and YAML,
// prints them in --help and --schema, and PourSpec::validate() checks a PourSpec against them.
#include <utility>

#include "core/error.hpp"
#include "engine/run_guard.hpp"
#include "protocol/pour.hpp"

namespace granudrag {

ParameterSpec skin_key() {
  return Key::number("skin").unit("d").default_value("0.2").above(0).help("Verlet-list skin");
}

const std::vector<ParameterSpec>& pour_keys() {
  static const std::vector<ParameterSpec> keys = {
      Key::number("lx").unit("d").default_value("20").at_least(4).help(
          "box length along x (periodic; the pull direction; >= 4 d for the periodic cells)"),
      Key::number("ly").unit("d").default_value("20").at_least(4).help("box width along y (periodic)"),
      Key::integer("grains").default_value("4000").at_least(1).at_most(1e9).help(
          "number of grains, diameters uniform in [0.9, 1.1] d"),
      Key::number("intruder_diameter")
          .unit("d")
          .default_value("2")
          .at_least(0)
          .help("D; 0 for a bed without intruder"),
      Key::number("intruder_x").unit("d").at_least(0).help("intruder centre x (default lx/2)"),
      Key::number("intruder_y").unit("d").at_least(0).help("intruder centre y (default ly/2)"),
      Key::number("depth").unit("d").above(0).help(
          "requested depth h of the intruder centre below the free surface"),
      Key::number("intruder_z").unit("d").above(0).help("or: height of the intruder centre above the wall"),
      Key::number("packing_estimate")
          .above(0.3)
          .below(0.75)
          .help(
              "packing fraction assumed to place the intruder at 'depth' (default: measured, 0.657 at mu = 0 "
              "to 0.598 at mu = 0.9)"),
      Key::number("fill_fraction")
          .default_value("0.3")
          .above(0)
          .at_most(0.35)
          .help(
              "packing fraction of the loose column the grains start in (random placement jams above ~0.38)"),
      Key::number("ke_threshold")
          .unit("rho g d^4")
          .default_value("1e-7")
          .above(0)
          .help("settled when the mean kinetic energy per grain is below"),
      Key::number("max_settle_time")
          .unit("sqrt(d/g)")
          .default_value("100")
          .above(0)
          .help("stop settling after this time anyway (recorded)"),
      Key::number("check_interval")
          .unit("sqrt(d/g)")
          .default_value("0.5")
          .above(0)
          .help("time between kinetic-energy checks"),
      Key::number("base_height")
          .unit("d")
          .default_value("0.6")
          .at_least(0)
          .help("grains with centre below are frozen into the rough base"),
      Key::integer("seed").default_value("1").at_least(0).at_most(9e18).help("random seed of the placement"),
  };
  return keys;
}

void PourSpec::validate() const {
  std::vector<std::pair<std::string, double>> values = {
      {"lx", lx},
      {"ly", ly},
      {"grains", static_cast<double>(grains)},
      {"intruder_diameter", intruder_diameter},
      {"fill_fraction", fill_fraction},
      {"ke_threshold", ke_threshold},
      {"max_settle_time", max_settle_time},
      {"check_interval", check_interval},
      {"base_height", base_height},
      {"seed", static_cast<double>(seed)},
      {"skin", skin},
      {"max_overlap", max_overlap},
  };
  if (intruder_diameter > 0) {
    values.emplace_back("intruder_x", intruder_x);
    values.emplace_back("intruder_y", intruder_y);
  }
  // NaN: not given (the other placement, or the measured packing).
  if (!std::isnan(depth)) values.emplace_back("depth", depth);
  if (!std::isnan(intruder_z)) values.emplace_back("intruder_z", intruder_z);
  if (!std::isnan(packing_estimate)) values.emplace_back("packing_estimate", packing_estimate);
  std::vector<ParameterSpec> keys = pour_keys();
  keys.push_back(skin_key());
  keys.push_back(max_overlap_key());
  check_ranges(keys, values, "pour settings");

  // What no single key's range can say.
  if (grains > 200 * lx * ly * 1000)
    throw Error("'grains' = " + std::to_string(grains) +
                " is out of range: more than a 1000 d tall bed in this box; use a wider box or fewer grains");
  if (intruder_diameter > 0) {
    if (!(intruder_x < lx))
      throw Error("'intruder_x' = " + std::to_string(intruder_x) +
                  " is out of range: the intruder must be inside the box: 0 <= intruder_x < lx = " +
                  std::to_string(lx));
    if (!(intruder_y < ly))
      throw Error("'intruder_y' = " + std::to_string(intruder_y) +
                  " is out of range: the intruder must be inside the box: 0 <= intruder_y < ly = " +
                  std::to_string(ly));
    if (std::isnan(depth) == std::isnan(intruder_z))
      throw Error(
          "give exactly one of 'depth' (below the free surface) and 'intruder_z' (height of "
          "the intruder centre above the wall)");
  }
  contact.validate();
}

}  // namespace granudrag
