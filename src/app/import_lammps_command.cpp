// granudrag import-lammps: a LAMMPS data file (atom_style sphere) as a granudrag bed.
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "app/command.hpp"
#include "app/output_paths.hpp"
#include "core/error.hpp"
#include "core/spatial_order.hpp"
#include "engine/simulation.hpp"
#include "io/lammps_io.hpp"
#include "io/run_files.hpp"
#include "protocol/bed_profile.hpp"
#include "protocol/pour.hpp"

namespace granudrag {

namespace {

std::vector<ParameterSpec> import_lammps_keys() {
  std::vector<ParameterSpec> keys = {
      Key::text("data").required().help("LAMMPS data file (atom_style sphere, density 1)"),
      output_key("bed file to write (HDF5)"),
      Key::integer("frozen_type")
          .default_value("2")
          .at_least(0)
          .at_most(1e9)
          .help("atom type of the frozen base grains (0: none)"),
      Key::integer("intruder_type")
          .default_value("3")
          .at_least(0)
          .at_most(1e9)
          .help("atom type of the intruder (0: none)"),
      Key::flag("sort").default_value("true").help(
          "put the grains in spatial order (thin layers along the longer horizontal axis, or along z when "
          "the bed is deeper than that axis is long; a Morton curve in the other two), the order a pull "
          "steps them in, so that the threaded force loop runs its two-colour schedule; false: keep the "
          "file's order"),
  };
  for (const auto& k : contact_keys().specs()) keys.push_back(k);
  keys.push_back(time_step_key());
  keys.push_back(skin_key());
  keys.push_back(threads_key());
  return keys;
}

}  // namespace

int import_lammps_command(const std::vector<std::string>& args) {
  const auto par = read_parameters(
      "import-lammps", import_lammps_keys(),
      "granudrag import-lammps — turn a LAMMPS data file into a granudrag bed (contact histories\n"
      "start at zero: data files do not carry them)",
      args);
  if (!par) return 0;
  const std::string out = par->text("output");
  check_output_dir(out, "output");
  std::vector<InputFile> inputs = config_inputs(args);
  inputs.push_back({"data", par->text("data")});
  const auto locks = claim_outputs(
      inputs, {{"output", out, "granudrag-bed"}, {"the sidecar", out + ".xdmf", "text", false}});
  const LammpsData data = read_lammps_data(par->text("data"), static_cast<int>(par->integer("frozen_type")),
                                           static_cast<int>(par->integer("intruder_type")));
  Bed bed;
  bed.box = data.box;
  Particles particles =
      par->flag("sort") ? reordered(data.particles, spatial_order(data.particles, data.box)) : data.particles;
  bed.contact = contact_from(*par);
  const double rmin =
      std::min(data.particles.min_radius(Species::Mobile), data.particles.min_radius(Species::Frozen));
  bed.dt = par->is_set("dt") ? par->number("dt")
                             : default_time_step(bed.contact, std::isfinite(rmin) ? rmin : 0.5);
  check_time_step(bed.dt, bed.contact, std::isfinite(rmin) ? rmin : 0.5);
  if (data.particles.count(Species::Intruder) > 1) throw Error("more than one intruder in the data file");
  bed.intruder =
      data.particles.count(Species::Intruder) == 1 ? static_cast<int>(data.particles.size()) - 1 : -1;
  // Forces of the imported state, with no history, as the first step of a pull needs them.
  Settings settings;
  settings.dt = bed.dt;
  settings.skin = par->number("skin");
  Simulation sim(particles, bed.box, bed.contact, settings);
  sim.setup();
  bed.state = sim.state();
  bed.profile = measure_bed(bed.state.particles, bed.box);
  bed.surface_height = bed.profile.surface_height;
  if (bed.intruder >= 0) bed.depth = bed.surface_height - bed.state.particles.x[bed.intruder].z();
  bed.stop_reason = "imported";
  save_bed(out, bed, *par);
  write_bed_xdmf(out, bed.state.particles.size());
  std::printf("bed: %s from %s\n  %zu particles (%zu frozen, %zu intruder), surface %.3f d, depth %.3f d\n",
              out.c_str(), par->text("data").c_str(), bed.state.particles.size(),
              bed.state.particles.count(Species::Frozen), bed.state.particles.count(Species::Intruder),
              bed.surface_height, bed.depth);
  return 0;
}

}  // namespace granudrag
