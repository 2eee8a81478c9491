#include "io/run_file.hpp"

#include <cmath>

#include "core/error.hpp"
#include "io/file_header.hpp"
#include "io/particle_data.hpp"

namespace granudrag {

void save_run(const std::string& path, const Pull& pull, const Parameters& pull_parameters,
              const ParameterRecord& bed_parameters, const std::string& sanity, FrameDump* frames,
              const ParameterRecord* placement) {
  const PullRecord& r = pull.record();
  const PullResult res = pull.result();
  const Bed& bed = pull.bed();
  h5::File f = h5::File::create(path);
  write_file_header(f, "granudrag-run");
  write_parameters(f, bed_parameters);
  if (placement != nullptr && !placement->command.empty()) write_parameters(f, *placement);
  write_parameters(f, ParameterRecord::of(pull_parameters));
  const Particles& p0 = bed.state.particles;
  const double D = 2 * p0.radius[bed.intruder];
  f.set_attr("/run", "D", D);
  f.set_attr("/run", "depth", bed.depth);
  f.set_attr("/run", "speed", pull.spec().speed);
  f.set_attr("/run", "froude", res.froude);
  f.set_attr("/run", "mu", bed.contact.mu);
  f.set_attr("/run", "kn", bed.contact.kn);
  f.set_attr("/run", "gamman", bed.contact.gamman);
  f.set_attr("/run", "dt", bed.dt);
  f.set_attr("/run", "steps", static_cast<std::int64_t>(r.total_steps));
  // Force on the intruder, averaged over each sample interval, as an H5MD time series.
  std::vector<std::int64_t> steps(r.time.size());
  std::vector<Vec3> force(r.time.size());
  for (std::size_t k = 0; k < r.time.size(); ++k) {
    steps[k] = static_cast<std::int64_t>((k + 1) * r.samples_per_interval);
    force[k] = Vec3(r.fx[k], r.fy[k], r.fz[k]);
  }
  f.write("/observables/intruder_force/step", steps);
  f.write("/observables/intruder_force/time", r.time);
  f.write_rows("/observables/intruder_force/value", force);
  f.set_attr("/observables/intruder_force", "meaning",
             std::string("force on the intruder (rho d^3 g), mean over each interval ending at time"));
  f.write("/observables/intruder_contacts/step", steps);
  f.write("/observables/intruder_contacts/time", r.time);
  f.write("/observables/intruder_contacts/value", r.contacts);
  f.write("/observables/cumulative_drag/value", res.cumulative_drag);
  if (const ActiveRegion* region = pull.simulation().active_region()) {
    f.write("/observables/sleeping_grains/step", steps);
    f.write("/observables/sleeping_grains/time", r.time);
    f.write("/observables/sleeping_grains/value", r.sleeping);
    f.set_attr("/observables/sleeping_grains", "wake_ups", static_cast<std::int64_t>(region->wake_ups()));
    f.set_attr("/observables/sleeping_grains", "sleeps", static_cast<std::int64_t>(region->state().sleeps));
    // The wake test used, which an unset wake_force leaves to the bed's K_n.
    f.set_attr("/observables/sleeping_grains", "wake_force", region->settings().wake_force);
    f.set_attr("/observables/sleeping_grains", "wake_load", region->settings().wake_load);
    f.set_attr(
        "/observables/sleeping_grains", "meaning",
        std::string(
            "active region (active_radius): grains asleep at the end of each interval; "
            "wake_ups and sleeps: how many times a grain woke or fell asleep in the pull; wake_force: the "
            "wake test used (an unset one is the default at the bed's K_n); wake_load: its part relative to "
            "the grain's contact load (0: none)"));
  }
  auto scalar = [&](const std::string& name, double value, double error, const std::string& meaning) {
    f.set_attr("/observables/" + name, "value", value);
    f.set_attr("/observables/" + name, "error", error);
    f.set_attr("/observables/" + name, "meaning", meaning);
  };
  scalar("drag", res.drag, res.drag_error,
         "-<F_x> after the transient (rho d^3 g); error: standard error of the mean from the "
         "integrated autocorrelation time (automatic window, mean-subtraction bias corrected)");
  // Student-t degrees of freedom of the error, and 1 when it converged (0: the series is short
  // for its correlations and the error is a conservative bound).
  f.set_attr("/observables/drag", "error_dof", res.drag_dof);
  f.set_attr("/observables/drag", "plateau", static_cast<std::int64_t>(res.drag_plateau ? 1 : 0));
  f.set_attr("/observables/drag", "transient_distance", res.transient_distance);
  // Sequential stopping: why the pull ended ("distance" or "target_error"), the target, and
  // the distance travelled.
  f.set_attr("/observables/drag", "stop_reason",
             r.stop_reason.empty() ? std::string("distance") : r.stop_reason);
  f.set_attr("/observables/drag", "target_error", pull.spec().target_error);
  f.set_attr("/observables/drag", "distance_travelled",
             r.total_steps * pull.simulation().dt() * pull.spec().speed);
  f.set_attr("/observables/drag", "transient_samples", static_cast<std::int64_t>(res.transient_samples));
  // How the drag and its error converge with travel: the first 8, 11, 16, ... samples after
  // the transient, then all of them (the pull-length validation's input).
  {
    const std::string g = "/observables/drag/convergence/";
    std::vector<double> travel, value, error, dof;
    std::vector<std::int64_t> samples, plateau;
    for (const PrefixError& p : res.drag_convergence) {
      samples.push_back(p.samples);
      travel.push_back(static_cast<double>(p.samples) * res.travel_per_sample);
      value.push_back(p.estimate.mean);
      error.push_back(p.estimate.error);
      dof.push_back(p.estimate.dof);
      plateau.push_back(p.estimate.plateau ? 1 : 0);
    }
    f.write(g + "samples", samples);
    f.write(g + "travel", travel);
    f.write(g + "value", value);
    f.write(g + "error", error);
    f.write(g + "dof", dof);
    f.write(g + "plateau", plateau);
    f.set_attr("/observables/drag/convergence", "meaning",
               std::string("-<F_x> and its error over the first `samples` samples after the transient "
                           "(`travel` d of it); the last row is the whole series"));
  }
  scalar("coordination", res.coordination, res.coordination_error,
         "n: mean number of grains touching the intruder; error: as the drag's");
  scalar(
      "theta", res.theta, res.theta_error,
      "mean angle between the intruder velocity and the intruder-to-grain line at contact formation (rad)");
  f.set_attr("/observables/theta", "error_dof", res.theta_dof);
  f.set_attr("/observables/theta", "error_method",
             std::string("the angles' sum and count per sample interval, the ratio's error by the "
                         "delta method and the drag's estimator (correlated formations counted as such)"));
  scalar("theta_present", res.theta_present, res.theta_present_error,
         "mean angle between the intruder velocity and the intruder-to-grain line over the contacts "
         "present at each sample after the transient (time-weighted; theta counts each contact once, "
         "at its formation), rad");
  f.set_attr("/observables/theta_present", "error_dof", res.theta_present_dof);
  f.write("/observables/theta_present/sum", r.theta_present_sum);
  f.write("/observables/theta_present/count", r.theta_present_count);
  f.set_attr("/observables/theta_present", "series_meaning",
             std::string("sum and count of the angles of the contacts present at the end of each sample "
                         "interval (every interval, the transient's too; NaN where a resumed checkpoint "
                         "did not record them)"));
  f.write("/observables/theta/histogram",
          std::vector<std::int64_t>(r.theta_histogram.begin(), r.theta_histogram.end()));
  scalar("bulk_coordination", res.bulk_coordination, NAN,
         "Z of mobile grains with centre within R + shell of the intruder");
  f.set_attr("/observables/bulk_coordination", "shell", pull.spec().shell);
  f.write("/observables/bulk_coordination/distribution", res.z_distribution);
  scalar("kappa", res.kappa, NAN, "(Z/n)(D+d)^2/(2 sqrt(3) d^2), paper Eq. 8");
  // Z and kappa in nested shells (protocol/coordination_shells.hpp): which "certain distance".
  const std::string shells = "/observables/bulk_coordination/shells/";
  f.write(shells + "width",
          std::vector<double>(CoordinationShells::widths.begin(), CoordinationShells::widths.end()));
  f.write(shells + "Z", res.shell_z);
  f.write(shells + "kappa", res.shell_kappa);
  f.write(shells + "grains", std::vector<std::int64_t>(r.shells.grains.begin(), r.shells.grains.end()));
  f.set_attr("/observables/bulk_coordination/shells", "meaning",
             std::string("Z and kappa of mobile grains with centre within R + width of the intruder, "
                         "the samples of Z; grains: sample-grains counted in each ring between widths"));
  write_snapshots(f, "/snapshots/", r.snapshots);
  f.set_attr("/sanity", "report", sanity);
  f.set_attr("/sanity", "max_overlap", r.max_overlap);
  f.set_attr("/sanity", "work", r.work);
  // "clean", or the first failure of a keep_going pull; the analysis uses clean runs only.
  f.set_attr("/sanity", "verdict", pull.verdict());
  f.set_attr("/sanity", "grains_lost", static_cast<std::int64_t>(r.grains_lost));
  f.set_attr("/sanity", "max_overlap_bound", pull.spec().max_overlap);
  if (frames) frames->write_into(f);
  f.commit();
}

}  // namespace granudrag
