// granudrag pour: pour and settle a bed around a fixed intruder.
#include <omp.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>

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

// The command's keys, in the order a bed file records them: PourSpec's (pour_keys()), the contact
// law's (read by contact_from) and the command's own, which control the run.
std::vector<ParameterSpec> pour_command_keys() {
  KeyTable<PourSpec> keys = pour_keys();
  keys.add_front({output_key("bed file to write (HDF5)")});
  std::vector<ParameterSpec> contact = contact_keys();
  contact.insert(contact.begin(), quiet_key());
  keys.add_before("dt", contact);
  keys.add({
      Key::number("checkpoint_interval")
          .unit("sqrt(d/g)")
          .default_value("0")
          .at_least(0)
          .help("simulated time between checkpoints (<output>.checkpoint.h5), rounded up to whole "
                "check_intervals; 0: none"),
      Key::flag("resume").default_value("false").help(
          "continue from <output>.checkpoint.h5 if it exists (bitwise as if never stopped, same threads)"),
      Key::number("dump_interval")
          .unit("sqrt(d/g)")
          .default_value("0")
          .at_least(0)
          .help("simulated time between frames (positions, velocities of every body, from step 0; "
                "rounded up to whole check_interval) written to the bed file's /particles/frames, "
                "with a temporal <output>.frames.xdmf for ParaView; 48 bytes per body per frame "
                "before compression; 0: none"),
      threads_key(),
  });
  return keys.specs();
}

// The keys that are PourSpec fields come from pour_keys() (dt among them, NaN when unset); the
// rest need the command: the intruder's default position is the centre of the box as given, and
// the contact law follows from several keys at once.
PourSpec pour_spec(const Parameters& par) {
  PourSpec s;
  pour_keys().read(par, s);
  s.intruder_x = par.is_set("intruder_x") ? par.number("intruder_x") : 0.5 * s.lx;
  s.intruder_y = par.is_set("intruder_y") ? par.number("intruder_y") : 0.5 * s.ly;
  if (s.intruder_diameter > 0 && std::isnan(s.depth) && std::isnan(s.intruder_z))
    throw Error("give 'depth' (below the free surface) or 'intruder_z' for the intruder");
  s.contact = contact_from(par);
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
  PourSpec s = pour_spec(*par);
  const std::string out = par->text("output");
  check_output_dir(out, "output");
  const std::string checkpoint = out + ".checkpoint.h5";
  const auto locks = claim_outputs(config_inputs(args),
                                   {{"output", out, "granudrag-bed"},
                                    {"the sidecar", out + ".xdmf", "text", false},
                                    {"the checkpoint", checkpoint, "granudrag-pour-checkpoint", false, true},
                                    {"the frames' sidecar", out + ".frames.xdmf", "text", false}});

  if (par->number("checkpoint_interval") > 0)
    s.checkpoint_every = std::max(
        1L, static_cast<long>(std::ceil(par->number("checkpoint_interval") / s.check_interval - 1e-9)));
  if (par->number("dump_interval") > 0)
    s.dump_every =
        std::max(1L, static_cast<long>(std::ceil(par->number("dump_interval") / s.check_interval - 1e-9)));

  const double t0 = omp_get_wtime();
  std::unique_ptr<FrameDump> frames;
  auto save = [&](const Pour& p) {
    if (frames) frames->seal();  // every frame the checkpoint counts is in a sealed segment
    save_pour_checkpoint(checkpoint, p, *par);
  };
  auto dump = [&](const Pour& p) {
    const Simulation& sim = p.simulation();
    frames->add(sim.steps_done(), sim.time(), sim.particles());
  };
  std::unique_ptr<Pour> pour;
  // A resumed pour must match every option but the run controls; an unreadable checkpoint is
  // moved aside and the pour starts over.
  std::optional<PourCheckpoint> c;
  if (par->flag("resume") && std::filesystem::exists(checkpoint))
    c = load_pour_checkpoint_or_move_aside(checkpoint, *par, {"resume", "quiet", "threads"});
  if (c) {
    pour = std::make_unique<Pour>(s, c->state, std::move(c->record));
    std::fprintf(stderr, "pour: resuming from %s at step %ld\n", checkpoint.c_str(),
                 pour->simulation().steps_done());
  } else {
    pour = std::make_unique<Pour>(s);
  }
  if (s.dump_every > 0)
    frames = std::make_unique<FrameDump>(out, pour->simulation().particles(), pour->record().frames);
  pour->run(!par->flag("quiet"), save, dump);
  const double wall = omp_get_wtime() - t0;
  Bed bed = pour->result();
  bed.sanity = pour->sanity_report(wall);
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
  std::printf("  wall time %.1f s\n%s", wall, bed.sanity.c_str());
  std::printf("%s", pour->timing_report().c_str());
  return 0;
}

}  // namespace granudrag
