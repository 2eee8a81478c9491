// granudrag place: put an intruder into a settled bed and let the bed settle around it again.
#include <omp.h>

#include <cmath>
#include <cstdio>

#include "app/command.hpp"
#include "app/output_paths.hpp"
#include "core/error.hpp"
#include "io/run_files.hpp"
#include "io/xdmf.hpp"
#include "protocol/placement.hpp"

namespace granudrag {

namespace {

std::vector<ParameterSpec> place_command_keys() {
  KeyTable<PlacementSpec> keys = placement_keys();
  keys.add_front(
      {Key::text("bed").required().help("source bed file, poured without an intruder (granudrag pour "
                                        "--intruder_diameter 0); it is read only"),
       output_key("bed file to write (HDF5)")});
  keys.add({quiet_key(), threads_key()});
  return keys.specs();
}

}  // namespace

int place_command(const std::vector<std::string>& args) {
  const auto par = read_parameters(
      "place", place_command_keys(),
      "granudrag place — put an intruder into a settled bed and settle the bed around it again\n\n"
      "  granudrag place --bed column.h5 --output bed.h5 --intruder_diameter D --depth h [--key value ...]\n"
      "  granudrag place --schema    (the keys as a JSON Schema)\n\n"
      "The grains the intruder's volume would cut at (intruder_x, intruder_y), depth h below the\n"
      "source bed's free surface, are removed (as LAMMPS delete_atoms overlap); the intruder is held\n"
      "there while the bed settles to ke_threshold again (at least min_settle_time, at most\n"
      "max_settle_time). The new bed records what was removed (/placement) and pulls like a poured\n"
      "one; one column serves every depth and D of its seed. The source bed is never changed.",
      args);
  if (!par) return 0;
  set_threads(*par);
  const std::string source_path = par->text("bed"), out = par->text("output");
  check_output_dir(out, "output");
  std::vector<InputFile> inputs = config_inputs(args);
  inputs.push_back({"bed", source_path});
  const auto locks = claim_outputs(
      inputs, {{"output", out, "granudrag-bed"}, {"the sidecar", out + ".xdmf", "text", false}});
  ParameterRecord source_parameters;
  const Bed source = load_bed(source_path, &source_parameters);
  PlacementSpec spec;
  placement_keys().read(*par, spec);
  // Settled again to the threshold its column was poured to, unless told otherwise; the threshold
  // used is recorded with the placement's parameters.
  Parameters recorded = *par;
  if (par->is_set("ke_threshold")) {
    spec.ke_threshold = par->number("ke_threshold");
  } else {
    if (const RecordedParameter* ke = source_parameters.find("ke_threshold")) spec.ke_threshold = ke->number;
    char text[32];
    std::snprintf(text, sizeof text, "%.17g", spec.ke_threshold);
    recorded.apply_cli({"--ke_threshold", text});
  }
  if (par->is_set("intruder_x")) spec.intruder_x = par->number("intruder_x");
  if (par->is_set("intruder_y")) spec.intruder_y = par->number("intruder_y");
  PlacementRecord record;
  const Bed placed = [&] {
    try {
      return placed_column(source, spec, &record);
    } catch (const Error& e) {
      throw Error("cannot place into '" + source_path + "': " + e.what());
    }
  }();
  const double t0 = omp_get_wtime();
  Placement settling(placed, spec);
  settling.run(!par->flag("quiet"));
  const double wall = omp_get_wtime() - t0;
  const Bed& bed = settling.result();
  save_placed_bed(out, bed, source_parameters, recorded, source_path, record);
  write_bed_xdmf(out, bed.state.particles.size());
  std::printf("bed: %s, from %s\n  intruder D = %g placed at depth %.3f d (z = %.3f d), %zu grains removed\n",
              out.c_str(), source_path.c_str(), spec.intruder_diameter, spec.depth, record.intruder_z,
              record.removed.size());
  std::printf("  settling stopped by %s at t = %.2f sqrt(d/g), kinetic energy per grain %.3g\n",
              bed.stop_reason.c_str(), bed.settle_time, bed.kinetic_energy);
  std::printf("  surface height %.3f d (source %.3f d), depth now h = %.3f d\n", bed.surface_height,
              record.source_surface_height, bed.depth);
  if (bed.stop_reason != "threshold")
    std::fprintf(stderr,
                 "place: warning: the bed did not settle to ke_threshold within max_settle_time = %g "
                 "(kinetic energy per grain %.3g): raise max_settle_time\n",
                 spec.max_settle_time, bed.kinetic_energy);
  std::printf("  wall time %.1f s\n%s%s", wall, bed.sanity.c_str(), settling.timing_report().c_str());
  return 0;
}

}  // namespace granudrag
