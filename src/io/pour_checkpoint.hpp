#pragma once
// The checkpoint of a pour (`<output>.checkpoint.h5`): the state reached, with its contact
// histories (io/particle_data.hpp), the run guard's figures under /pour (energy_start,
// max_overlap_seen, grains_lost), and the pour's resolved parameters (/parameters/pour). A pour
// resumes from it only with the same parameters (run controls aside).
#include <optional>
#include <string>
#include <vector>

#include "core/parameters.hpp"
#include "protocol/pour.hpp"

namespace granudrag {

void save_pour_checkpoint(const std::string& path, const Pour& pour, const Parameters& pour_parameters);

struct PourCheckpoint {
  Simulation::State state;
  PourRecord record;
};

// Refuses (an Error naming the file, every difference and what to do) a checkpoint written by a
// pour whose parameters differ from `now` in any key but `run_controls`; a damaged one, or one of
// another format or version, throws UnreadableCheckpoint.
PourCheckpoint load_pour_checkpoint(const std::string& path, const Parameters& now,
                                    const std::vector<std::string>& run_controls);

// load_pour_checkpoint, except that an unreadable checkpoint is moved aside to `<path>.corrupt`
// and nothing is returned: the pour starts over, so a retry always makes progress.
std::optional<PourCheckpoint> load_pour_checkpoint_or_move_aside(
    const std::string& path, const Parameters& now, const std::vector<std::string>& run_controls);

}  // namespace granudrag
