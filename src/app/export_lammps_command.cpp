// granudrag export-lammps: a bed as a LAMMPS data file plus an input script running the same pull.
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "app/command.hpp"
#include "app/output_paths.hpp"
#include "core/error.hpp"
#include "io/lammps_io.hpp"
#include "io/run_files.hpp"

namespace granudrag {

int export_lammps_command(const std::vector<std::string>& args) {
  const auto par = read_parameters(
      "export-lammps",
      {
          Key::text("bed").required().help("bed file from granudrag pour"),
          output_key("prefix: writes PREFIX.data and PREFIX.in"),
          Key::number("speed").unit("sqrt(g d)").default_value("1").above(0).help("pulling speed V along +x"),
          Key::number("distance").unit("d").default_value("0").at_least(0).help("travel; 0: one box length"),
          Key::integer("steps").default_value("0").at_least(0).at_most(1e15).help(
              "or: number of steps (overrides distance)"),
          Key::integer("every").default_value("1").at_least(1).at_most(1e15).help(
              "steps per line of the force file (averaged)"),
          skin_key(),
      },
      "granudrag export-lammps — write a bed as a LAMMPS data file plus an input script that runs\n"
      "the same pull with gran/hertz/history (run it as: cd DIR && lmp -in PREFIX.in)",
      args);
  if (!par) return 0;
  const std::string prefix = par->text("output");
  check_output_dir(prefix, "output");
  std::vector<InputFile> inputs = config_inputs(args);
  inputs.push_back({"bed", par->text("bed")});
  const auto locks = claim_outputs(
      inputs, {{"the data file", prefix + ".data", "text"}, {"the input script", prefix + ".in", "text"}});
  const Bed bed = load_bed(par->text("bed"));
  if (bed.intruder < 0) throw Error("bed '" + par->text("bed") + "' has no intruder to pull");
  Particles p = bed.state.particles;
  const double speed = par->number("speed");
  p.v[bed.intruder] = Vec3(speed, 0, 0);
  double ztop = 0;
  for (const Vec3& x : p.x) ztop = std::max(ztop, x.z());
  write_lammps_data(prefix + ".data", p, bed.box, ztop + 2.0 * p.max_radius(Species::Intruder) + 2.0);
  LammpsPull run;
  const std::string base = prefix.substr(prefix.find_last_of('/') + 1);
  run.data_file = base + ".data";
  run.force_file = base + ".force.txt";
  run.contact = bed.contact;
  run.dt = bed.dt;
  run.skin = par->number("skin");
  run.speed = speed;
  const double distance = par->number("distance") > 0 ? par->number("distance") : bed.box.lx;
  run.steps =
      par->integer("steps") > 0 ? par->integer("steps") : std::lround(std::ceil(distance / (speed * bed.dt)));
  run.every = par->integer("every");
  run.intruder_id = bed.intruder + 1;
  write_lammps_pull_input(prefix + ".in", run);
  std::printf("wrote %s.data and %s.in (%ld steps; force on the intruder to %s)\n", prefix.c_str(),
              prefix.c_str(), run.steps, run.force_file.c_str());
  return 0;
}

}  // namespace granudrag
