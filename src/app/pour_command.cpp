// granudrag pour: pour and settle a bed around a fixed intruder.
#include <omp.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>

#include "app/command.hpp"
#include "app/output_paths.hpp"
#include "core/error.hpp"
#include "engine/run_guard.hpp"
#include "io/frame_dump.hpp"
#include "io/pour_checkpoint.hpp"
#include "io/run_files.hpp"
#include "io/xdmf.hpp"
#include "protocol/pour.hpp"

namespace granudrag {

namespace {

// The command's keys, in the order a bed file records them.
std::vector<ParameterSpec> pour_command_keys() {
  std::vector<ParameterSpec> keys = {output_key("bed file to write (HDF5)")};
  for (const auto& k : pour_keys()) keys.push_back(k);
  keys.push_back(quiet_key());
  for (const auto& k : contact_keys()) keys.push_back(k);
  keys.push_back(skin_key());
  keys.push_back(max_overlap_key());
  keys.push_back(Key::number("checkpoint_interval")
                     .unit("sqrt(d/g)")
                     .default_value("0")
                     .at_least(0)
                     .help("simulated time between checkpoints (<output>.checkpoint.h5), rounded up to whole "
                           "check_intervals; 0: none"));
  keys.push_back(Key::flag("resume").default_value("false").help(
      "continue from <output>.checkpoint.h5 if it exists (bitwise as if never stopped, same threads)"));
  keys.push_back(Key::number("dump_interval")
                     .unit("sqrt(d/g)")
                     .default_value("0")
                     .at_least(0)
                     .help("simulated time between frames (positions, velocities of every body, from step 0; "
                           "rounded up to whole check_interval) written to the bed file's /particles/frames, "
                           "with a temporal <output>.frames.xdmf for ParaView; 48 bytes per body per frame "
                           "before compression; 0: none"));
  keys.push_back(threads_key());
  return keys;
}

PourSpec pour_spec(const Parameters& par) {
  PourSpec s;
  s.lx = par.number("lx");
  s.ly = par.number("ly");
  s.grains = par.integer("grains");
  s.intruder_diameter = par.number("intruder_diameter");
  s.intruder_x = par.is_set("intruder_x") ? par.number("intruder_x") : 0.5 * s.lx;
  s.intruder_y = par.is_set("intruder_y") ? par.number("intruder_y") : 0.5 * s.ly;
  if (par.is_set("depth")) s.depth = par.number("depth");
  if (par.is_set("intruder_z")) s.intruder_z = par.number("intruder_z");
  if (s.intruder_diameter > 0 && std::isnan(s.depth) && std::isnan(s.intruder_z))
    throw Error("give 'depth' (below the free surface) or 'intruder_z' for the intruder");
  if (par.is_set("packing_estimate")) s.packing_estimate = par.number("packing_estimate");
  s.fill_fraction = par.number("fill_fraction");
  s.contact = contact_from(par);
  if (par.is_set("dt")) s.dt = par.number("dt");
  s.skin = par.number("skin");
  s.ke_threshold = par.number("ke_threshold");
  s.max_settle_time = par.number("max_settle_time");
  s.check_interval = par.number("check_interval");
  s.base_height = par.number("base_height");
  s.seed = static_cast<std::uint64_t>(par.integer("seed"));
  s.max_overlap = par.number("max_overlap");
  return s;
}

}  // namespace

int pour_command(const std::vector<std::string>& args) {
  const auto par =
      read_parameters("pour", pour_command_keys(),
                      "granudrag pour — pour and settle a bed around a fixed intruder\n\n"
                      "  granudrag pour --output bed.h5 [--config pour.yaml] [--key value ...]\n"
                      "  granudrag pour --schema    (the keys as a JSON Schema)\n\n"
                      "A pour stops (exit 1, the last checkpoint kept) at NaN or inf, a grain out of the\n"
                      "box (below the wall, 10 d above the starting column), an overlap > max_overlap, or\n"
                      "a gain of the grains' energy of more than 1 rho g d^4 per grain; it is checked every\n"
                      "check_interval. With checkpoint_interval > 0, --resume continues a killed pour\n"
                      "bit for bit as if it had not been stopped (same thread count).",
                      args);
  if (!par) return 0;
  set_threads(*par);
  const PourSpec s = pour_spec(*par);
  const std::string out = par->text("output");
  check_output_dir(out, "output");
  const std::string checkpoint = out + ".checkpoint.h5";
  const auto locks = claim_outputs(config_inputs(args),
                                   {{"output", out, "granudrag-bed"},
                                    {"the sidecar", out + ".xdmf", "text", false},
                                    {"the checkpoint", checkpoint, "granudrag-pour-checkpoint", false, true},
                                    {"the frames' sidecar", out + ".frames.xdmf", "text", false}});

  const double t0 = omp_get_wtime();
  PourCheckpoints checkpoints;
  PourState resumed;
  if (par->number("checkpoint_interval") > 0) {
    const double every = std::ceil(par->number("checkpoint_interval") / s.check_interval - 1e-9);
    checkpoints.every = std::max(1L, static_cast<long>(every));
    checkpoints.save = [&](const PourState& state) {
      save_pour_checkpoint(checkpoint, state, state.dt, *par);
    };
  }
  if (par->flag("resume") && std::filesystem::exists(checkpoint)) {
    if (auto c = load_pour_checkpoint_or_move_aside(checkpoint, *par, {"resume", "quiet", "threads"})) {
      resumed = std::move(*c);
      checkpoints.resume_from = &resumed;
      std::fprintf(stderr, "pour: resuming from %s at step %ld\n", checkpoint.c_str(), resumed.state.steps);
    }
  }
  // Frames: the dump is made at the first frame (the pour places the grains), knowing how many
  // frames the checkpoint resumed from counts.
  std::unique_ptr<FrameDump> frames;
  if (par->number("dump_interval") > 0) {
    checkpoints.frame_every =
        std::max(1L, static_cast<long>(std::ceil(par->number("dump_interval") / s.check_interval - 1e-9)));
    checkpoints.frame = [&](const Simulation& sim) {
      if (!frames) frames = std::make_unique<FrameDump>(out, sim.particles(), resumed.frames);
      frames->add(sim.steps_done(), sim.time(), sim.particles());
    };
    if (checkpoints.save) {
      checkpoints.save = [&](const PourState& state) {
        if (frames) frames->seal();  // every frame the checkpoint counts is in a sealed segment
        save_pour_checkpoint(checkpoint, state, state.dt, *par);
      };
    }
  }
  const Bed bed = pour(s, !par->flag("quiet"), checkpoints);
  if (checkpoints.frame_every > 0 && !frames)
    frames = std::make_unique<FrameDump>(out, bed.state.particles, resumed.frames);
  save_bed(out, bed, *par, frames.get());
  std::filesystem::remove(checkpoint);
  write_bed_xdmf(out, bed.state.particles.size());
  if (frames) {
    frames->remove_segments();
    write_frames_xdmf(out + ".frames.xdmf", std::filesystem::path(out).filename().string(),
                      bed.state.particles.size(), frame_times(out));
    std::printf("  %ld frames in /particles/frames, for ParaView: %s.frames.xdmf\n", frames->frames(),
                out.c_str());
  }
  std::printf("bed: %s\n  grains %ld (%zu frozen in the base), box %g x %g, dt %.4g\n", out.c_str(), s.grains,
              bed.state.particles.count(Species::Frozen), s.lx, s.ly, bed.dt);
  std::printf("  settling stopped by %s at t = %.2f sqrt(d/g), kinetic energy per grain %.3g\n",
              bed.stop_reason.c_str(), bed.settle_time, bed.kinetic_energy);
  std::printf("  surface height %.3f d (half bulk packing), bulk packing fraction %.4f\n", bed.surface_height,
              bed.profile.bulk_packing_fraction);
  if (bed.intruder >= 0)
    std::printf(
        "  intruder D = %g at depth h = %.3f d (requested %s)\n", s.intruder_diameter, bed.depth,
        std::isnan(bed.requested_depth) ? "by intruder_z" : std::to_string(bed.requested_depth).c_str());
  std::printf("  wall time %.1f s\n%s", omp_get_wtime() - t0, bed.sanity.c_str());
  return 0;
}

}  // namespace granudrag
