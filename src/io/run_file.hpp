#pragma once
// The run file (`granudrag pull`): one pull's results.
//   /run                      D, depth, speed, froude, mu, kn, gamman, dt, steps
//   /observables              intruder_force and intruder_contacts (H5MD series per sample
//                             interval), cumulative_drag, and drag, coordination (n), theta,
//                             bulk_coordination (Z, with P(Z)), kappa: value, error, meaning;
//                             drag also error_dof (Student-t) and plateau (1: error converged)
//   /snapshots/<k>            velocity snapshots of the slab through the intruder
//   /sanity                   the sanity report, max_overlap, work, verdict ("clean" or the
//                             first failure of a keep_going pull), grains_lost, max_overlap_bound
//   /parameters/pull          the pull's resolved parameters; /parameters/pour: its bed's,
//                             copied from the bed file (io/parameter_record.hpp), and for a
//                             placed bed (granudrag place) its /parameters/place too
//   /particles/frames         with --dump_interval: every body's position and velocity per frame
//                             (io/frame_dump.hpp)
#include <string>

#include "core/parameters.hpp"
#include "io/frame_dump.hpp"
#include "io/parameter_record.hpp"
#include "protocol/pull.hpp"

namespace granudrag {

// `pull_parameters`: the pull's resolved parameters; `bed_parameters`: its bed's (load_bed);
// `frames`: the pull's frames, or null; `placement`: a placed bed's /parameters/place (load_bed),
// or null (or a record without a command) for a poured bed.
void save_run(const std::string& path, const Pull& pull, const Parameters& pull_parameters,
              const ParameterRecord& bed_parameters, const std::string& sanity, FrameDump* frames = nullptr,
              const ParameterRecord* placement = nullptr);

}  // namespace granudrag
