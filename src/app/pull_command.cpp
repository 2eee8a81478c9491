// granudrag pull: pull the intruder of a bed at constant speed and record the drag.
#include <omp.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <sstream>

#include "app/command.hpp"
#include "app/output_paths.hpp"
#include "core/error.hpp"
#include "io/frame_dump.hpp"
#include "io/run_files.hpp"
#include "io/xdmf.hpp"
#include "protocol/pull.hpp"

namespace granudrag {

namespace {

// The command's keys, in the order a run file records them: PullSpec's (pull_keys()) and the
// command's own, which control the run rather than what it computes.
std::vector<ParameterSpec> pull_command_keys() {
  KeyTable<PullSpec> keys = pull_keys();
  keys.add_front({
      Key::text("bed").required().help("bed file from granudrag pour"),
      output_key("run file to write (HDF5)"),
  });
  keys.add_before(
      "skin",
      {
          Key::number("checkpoint_interval")
              .unit("sqrt(d/g)")
              .default_value("0")
              .at_least(0)
              .help(
                  "simulated time between checkpoints (<output>.checkpoint.h5); 0: every tenth of the pull"),
          Key::flag("resume").default_value("false").help(
              "continue from <output>.checkpoint.h5 if it exists"),
          Key::number("dump_interval")
              .unit("sqrt(d/g)")
              .default_value("0")
              .at_least(0)
              .help(
                  "simulated time between frames (positions, velocities of every body, from step 0) written "
                  "to the run file's /particles/frames, with a temporal <output>.xdmf for ParaView; 48 bytes "
                  "per body per frame before compression; 0: none"),
      });
  keys.add({threads_key(), quiet_key()});
  return keys.specs();
}

}  // namespace

int pull_command(const std::vector<std::string>& args) {
  const auto found = read_parameters(
      "pull", pull_command_keys(),
      "granudrag pull — pull the intruder of a bed at constant speed and record the drag\n\n"
      "  granudrag pull --bed bed.h5 --output run.h5 [--speed V | --froude Fr] [--key value ...]\n"
      "  granudrag pull --schema    (the keys as a JSON Schema)\n\n"
      "A speed the bed cannot resolve is refused before any work, with the largest that works: the\n"
      "undamped Hertz overlap of one impact of the intruder on the largest grain at rest must be\n"
      "<= max_overlap; the impact on the smallest grain must last >= 16 steps of dt (the bed's, or\n"
      "the one collision_steps sets); and V dt <= skin/10. A running pull stops (exit 1, the last\n"
      "checkpoint kept) at NaN or inf, a grain out of the box, an overlap > max_overlap, or a gain of\n"
      "the grains' energy over the work done on them of more than 1 rho g d^4 per grain; the run file\n"
      "records its verdict in /sanity.",
      args);
  if (!found) return 0;
  const Parameters& par = *found;
  set_threads(par);
  const std::string bed_path = par.text("bed"), out = par.text("output");
  check_output_dir(out, "output");
  std::vector<InputFile> inputs = config_inputs(args);
  inputs.push_back({"bed", bed_path});
  const auto locks =
      claim_outputs(inputs, {{"output", out, "granudrag-run"},
                             {"the checkpoint", out + ".checkpoint.h5", "granudrag-checkpoint", false, true},
                             {"the frames' sidecar", out + ".xdmf", "text", false}});
  ParameterRecord bed_parameters, placement;  // placement: a placed bed's /parameters/place
  Bed bed = load_bed(bed_path, &bed_parameters, &placement);
  if (bed.intruder < 0) throw Error("bed '" + bed_path + "' has no intruder to pull");
  PullSpec spec;
  pull_keys().read(par, spec);
  bed.dt = pull_time_step(spec, bed);
  const double D = 2 * bed.state.particles.radius[bed.intruder];
  spec.speed = pull_speed(par, D);
  spec.active.radius = pull_active_radius(par, D);
  {
    const double distance = spec.distance > 0 ? spec.distance : bed.box.lx;
    const double total_time = distance / spec.speed;
    const double interval =
        par.number("checkpoint_interval") > 0 ? par.number("checkpoint_interval") : total_time / 10;
    spec.checkpoint_every = std::max(1L, std::lround(interval / bed.dt));
    if (par.number("dump_interval") > 0)
      spec.dump_every = std::max(1L, std::lround(par.number("dump_interval") / bed.dt));
  }
  const std::string checkpoint = out + ".checkpoint.h5";

  const double t0 = omp_get_wtime();
  std::unique_ptr<FrameDump> frames;
  auto save = [&](const Pull& p) {
    if (frames) frames->seal();  // every frame the checkpoint counts is in a sealed segment
    save_checkpoint(checkpoint, p, par, bed_parameters);
  };
  auto dump = [&](const Pull& p) {
    const Simulation& sim = p.simulation();
    frames->add(sim.steps_done(), static_cast<double>(sim.steps_done()) * sim.dt(),
                p.particles_in_bed_order());
  };
  std::unique_ptr<Pull> pull;
  // A resumed pull must match every option but the run controls, and the bed itself; an
  // unreadable checkpoint is moved aside and the pull starts over.
  std::optional<Checkpoint> c;
  if (par.flag("resume") && std::filesystem::exists(checkpoint))
    c = load_checkpoint_or_move_aside(checkpoint, bed, par, {"resume", "quiet", "threads"});
  if (c) {
    pull = std::make_unique<Pull>(bed, spec, c->state, std::move(c->record));
    std::fprintf(stderr, "pull: resuming from %s at step %ld\n", checkpoint.c_str(),
                 pull->simulation().steps_done());
  } else {
    pull = std::make_unique<Pull>(bed, spec);
  }
  if (spec.dump_every > 0)
    frames = std::make_unique<FrameDump>(out, bed.state.particles, pull->record().frames);
  pull->run(!par.flag("quiet"), save, dump);
  const double wall = omp_get_wtime() - t0;
  const std::string sanity = pull->sanity_report(wall);
  save_run(out, *pull, par, bed_parameters, sanity, frames.get(), &placement);
  if (frames) {
    frames->remove_segments();
    write_frames_xdmf(out + ".xdmf", std::filesystem::path(out).filename().string(),
                      bed.state.particles.size(), frame_times(out));
  }
  std::filesystem::remove(checkpoint);
  const PullResult r = pull->result();
  std::printf("run: %s\n  D = %g, depth %.3f d, V = %.4g sqrt(gd), Fr = %.4g, mu = %g, kn = %g\n",
              out.c_str(), D, bed.depth, spec.speed, r.froude, bed.contact.mu, bed.contact.kn);
  // mean_error needs 8 samples after the transient: a shorter pull has a mean but no error.
  auto plus_minus = [](double error) {
    char text[32] = "";
    if (!std::isnan(error)) std::snprintf(text, sizeof text, " +- %.2g", error);
    return std::string(text);
  };
  std::printf("  drag = %.5g%s rho d^3 g (transient %.3g d discarded: %ld of %zu samples%s)\n", r.drag,
              plus_minus(r.drag_error).c_str(), r.transient_distance, r.transient_samples,
              pull->record().fx.size(), std::isnan(r.drag_error) ? "; no error: under 8 samples left" : "");
  std::printf("  n = %.3f, theta = %.4f%s rad, Z = %.3f, kappa = %.4f\n", r.coordination, r.theta,
              plus_minus(r.theta_error).c_str(), r.bulk_coordination, r.kappa);
  if (spec.target_error > 0)
    std::printf("  stopped by %s after %.4g d (target: relative error %.3g)\n",
                pull->record().stop_reason.c_str(),
                pull->record().total_steps * pull->simulation().dt() * spec.speed, spec.target_error);
  if (frames)
    std::printf("  %ld frames in /particles/frames, for ParaView: %s.xdmf\n", frames->frames(), out.c_str());
  std::printf("%s  verdict: %s\n", sanity.c_str(), pull->verdict().c_str());
  std::printf("%s", pull->timing_report().c_str());
  return 0;
}

}  // namespace granudrag
