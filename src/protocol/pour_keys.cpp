// The keys of a pour, declared once and bound to PourSpec's fields: `granudrag pour` reads them
// from the command line and YAML into a PourSpec, prints them in --help and --schema, and
// PourSpec::validate() checks a PourSpec against them.
#include <utility>

#include "contact/contact_keys.hpp"
#include "core/error.hpp"
#include "engine/run_guard.hpp"
#include "protocol/pour.hpp"

namespace granudrag {

ParameterSpec skin_key() {
  return Key::number("skin")
      .unit("d")
      .default_value(number_text(kDefaultSkin))
      .above(0)
      .help("Verlet-list skin");
}

const KeyTable<PourSpec>& pour_keys() {
  static const KeyTable<PourSpec> keys = {
      Key::number("lx")
          .unit("d")
          .at_least(4)
          .help("box length along x (periodic; the pull direction; >= 4 d for the periodic cells)")
          .field(&PourSpec::lx),
      Key::number("ly").unit("d").at_least(4).help("box width along y (periodic)").field(&PourSpec::ly),
      Key::integer("grains")
          .at_least(1)
          .at_most(1e9)
          .help("number of grains, diameters uniform in [0.9, 1.1] d")
          .field(&PourSpec::grains),
      Key::number("intruder_diameter")
          .unit("d")
          .at_least(0)
          .help("D; 0 for a bed without intruder")
          .field(&PourSpec::intruder_diameter),
      // Not bound: the default is the box's centre, whatever lx and ly are, and the position is
      // checked only when there is an intruder (pour_spec in pour_command.cpp, validate below).
      Key::number("intruder_x").unit("d").at_least(0).help("intruder centre x (default lx/2)"),
      Key::number("intruder_y").unit("d").at_least(0).help("intruder centre y (default ly/2)"),
      Key::number("depth")
          .unit("d")
          .above(0)
          .help("requested depth h of the intruder centre below the free surface")
          .field(&PourSpec::depth),
      Key::number("intruder_z")
          .unit("d")
          .above(0)
          .help("or: height of the intruder centre above the wall")
          .field(&PourSpec::intruder_z),
      Key::number("packing_estimate")
          .above(0.3)
          .below(0.75)
          .help(
              "packing fraction assumed to place the intruder at 'depth' (default: measured, 0.657 at mu = 0 "
              "to 0.598 at mu = 0.9)")
          .field(&PourSpec::packing_estimate),
      Key::number("fill_fraction")
          .above(0)
          .at_most(0.35)
          .help(
              "packing fraction of the loose column the grains start in (random placement jams above ~0.38)")
          .field(&PourSpec::fill_fraction),
      Key::number("ke_threshold")
          .unit("rho g d^4")
          .above(0)
          .help("settled when the mean kinetic energy per grain is below")
          .field(&PourSpec::ke_threshold),
      Key::number("max_settle_time")
          .unit("sqrt(d/g)")
          .above(0)
          .help("stop settling after this time anyway (recorded)")
          .field(&PourSpec::max_settle_time),
      Key::number("check_interval")
          .unit("sqrt(d/g)")
          .above(0)
          .help("time between kinetic-energy checks")
          .field(&PourSpec::check_interval),
      Key::number("settle_damping")
          .unit("sqrt(g/d)")
          .at_least(0)
          .help("a viscous drag -settle_damping m v (and torque -settle_damping I omega) on every "
                "grain once the top of the column could have fallen to the wall, as LAMMPS fix "
                "viscous: drains the slow elastic breathing of a deep bed, which an active-region "
                "pull at the yield speed needs at rest; 0: off (the paper's pour)")
          .field(&PourSpec::settle_damping),
      Key::number("base_height")
          .unit("d")
          .at_least(0)
          .help("grains with centre below are frozen into the rough base")
          .field(&PourSpec::base_height),
      Key::integer("seed")
          .at_least(0)
          .at_most(9e18)
          .help("random seed of the placement")
          .field(&PourSpec::seed),
      // Rows that other commands share (their defaults must be PourSpec's).
      Key(time_step_key()).field(&PourSpec::dt),
      Key(skin_key()).field(&PourSpec::skin),
      Key(max_overlap_key()).field(&PourSpec::max_overlap),
  };
  return keys;
}

void PourSpec::validate() const {
  std::vector<std::pair<std::string, double>> placement;
  if (intruder_diameter > 0) placement = {{"intruder_x", intruder_x}, {"intruder_y", intruder_y}};
  pour_keys().check(*this, "pour settings", placement);

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
