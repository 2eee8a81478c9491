#include "app/command.hpp"

#include <omp.h>

#include <cmath>
#include <filesystem>
#include <iostream>

#include "core/error.hpp"
#include "protocol/pull.hpp"

namespace granudrag {

const std::vector<Command>& commands() {
  static const std::vector<Command> list = {
      {"pour", pour_command},
      {"place", place_command},
      {"pull", pull_command},
      {"export-lammps", export_lammps_command},
      {"import-lammps", import_lammps_command},
      {"restitution", restitution_command},
      {"bench", bench_command},
      {"info", info_command},
  };
  return list;
}

bool wants_help(const std::vector<std::string>& args) {
  for (const auto& a : args)
    if (a == "--help" || a == "-h") return true;
  return false;
}

std::optional<Parameters> read_parameters(const std::string& command, std::vector<ParameterSpec> keys,
                                          const std::string& intro, const std::vector<std::string>& args) {
  Parameters par(command, std::move(keys));
  if (wants_help(args)) {
    std::cout << intro << "\n\n" << par.help_text();
    return std::nullopt;
  }
  for (const auto& a : args)
    if (a == "--schema") {
      std::cout << par.schema_json();
      return std::nullopt;
    }
  par.apply_cli(args);
  par.validate();
  return par;
}

ParameterSpec output_key(const std::string& help) { return Key::text("output").required().help(help); }

ParameterSpec threads_key() {
  return Key::integer("threads").default_value("0").at_least(0).at_most(4096).help(
      "OpenMP threads (0: OMP_NUM_THREADS or all cores)");
}

ParameterSpec quiet_key() {
  return Key::flag("quiet").default_value("false").help("no progress lines on stderr");
}

ContactParams contact_from(const Parameters& p) {
  ContactParams c;
  if (p.is_set("youngs_modulus")) {
    if (p.is_set("kt") || p.is_set("kn"))
      throw Error("give either 'youngs_modulus' (with 'poisson_ratio') or 'kn'/'kt', not both");
    c = ContactParams::from_young(p.number("youngs_modulus"), p.number("poisson_ratio"), 0, 0, 0);
    c.gamman = ContactParams{}.with_stiffness(c.kn).gamman;
  } else {
    c = ContactParams{}.with_stiffness(p.is_set("kn") ? p.number("kn") : ContactParams{}.kn);
    if (p.is_set("kt")) c.kt = p.number("kt");
  }
  if (p.is_set("gamman")) c.gamman = p.number("gamman");
  c.gammat = p.is_set("gammat") ? p.number("gammat") : c.gamman;
  contact_keys().read(p, c);  // the keys that are a plain field (mu)
  c.validate();
  return c;
}

void set_threads(const Parameters& p) {
  const long t = p.integer("threads");
  if (t > 0) omp_set_num_threads(static_cast<int>(t));
}

void check_output_dir(const std::string& path, const std::string& key) {
  const std::filesystem::path dir = std::filesystem::path(path).parent_path();
  if (!dir.empty() && !std::filesystem::is_directory(dir))
    throw Error("'" + key + "' = " + path + ": directory " + dir.string() +
                " does not exist; create it first");
}

double pull_speed(const Parameters& p, double intruder_diameter) {
  if (p.is_set("speed") && p.is_set("froude")) throw Error("give either 'speed' or 'froude', not both");
  if (p.is_set("froude")) return p.number("froude") / froude_number(1.0, intruder_diameter);
  return p.is_set("speed") ? p.number("speed") : PullSpec{}.speed;
}

double pull_time_step(const PullSpec& spec, const Bed& bed) {
  if (std::isnan(spec.collision_steps)) return bed.dt;
  const Particles& grains = bed.state.particles;
  double rmin = grains.min_radius(Species::Mobile);
  if (!std::isfinite(rmin)) rmin = 0.5;
  const double dt = shortest_collision_time(bed.contact, rmin) / spec.collision_steps;
  check_time_step(dt, bed.contact, rmin);
  return dt;
}

double pull_active_radius(const Parameters& p, double intruder_diameter) {
  const double radius = p.number("active_radius");
  if (!p.is_set("active_diameters")) return radius;
  if (radius > 0) throw Error("give either 'active_radius' (in d) or 'active_diameters' (in D), not both");
  return p.number("active_diameters") * intruder_diameter;
}

}  // namespace granudrag
