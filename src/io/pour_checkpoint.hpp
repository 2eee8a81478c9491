#pragma once
// The checkpoint of a pour (`<output>.checkpoint.h5`): the state reached, with its contact
// histories (io/particle_data.hpp), the run guard's figures under /pour (energy_start,
// max_overlap_seen, grains_lost), and the pour's resolved parameters (/parameters/pour). A pour
// resumes from it only with the same parameters (run controls aside).
#include <string>
#include <vector>

#include "core/parameters.hpp"
#include "protocol/pour.hpp"

namespace granudrag {

void save_pour_checkpoint(const std::string& path, const PourState& state, double dt,
                          const Parameters& pour_parameters);

// Refuses (an Error naming the file, every difference and what to do) a checkpoint written by a
// pour whose parameters differ from `now` in any key but `run_controls`, or of another format.
PourState load_pour_checkpoint(const std::string& path, const Parameters& now,
                               const std::vector<std::string>& run_controls);

}  // namespace granudrag
