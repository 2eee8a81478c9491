#pragma once
// The checkpoint of a pull (`<output>.checkpoint.h5`): the bed's groups with the state reached
// (io/bed_file.hpp), the pull's record so far under /pull, the bed's parameters and the pull's
// (/parameters/pour, /parameters/pull), and /pull attribute bed_fingerprint. A pull resumes from
// it only with the same options and the same bed.
#include <optional>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "core/parameters.hpp"
#include "io/parameter_record.hpp"
#include "io/unreadable_checkpoint.hpp"
#include "protocol/pull.hpp"

namespace granudrag {

// `pull_parameters`: the pull's resolved parameters; `bed_parameters`: its bed's (load_bed).
void save_checkpoint(const std::string& path, const Pull& pull, const Parameters& pull_parameters,
                     const ParameterRecord& bed_parameters);

struct Checkpoint {
  Simulation::State state;
  PullRecord record;
};
// A hash of a bed's particles (positions, radii, species): tells two beds apart.
std::string bed_fingerprint(const Bed& bed);

// Reads the checkpoint at `path` of a pull on `bed` with the parameters `now`. Refuses it (an
// Error naming the file and every difference, and what to do) when it was written for another
// bed or by a pull whose options differ from `now` in any key but `run_controls` (keys that do
// not change the result, such as quiet); also when it is damaged or of another format version.
// Throws UnreadableCheckpoint for a damaged file, Error for one written for another bed or with
// other options (that one is kept: it is the user's to decide).
Checkpoint load_checkpoint(const std::string& path, const Bed& bed, const Parameters& now,
                           const std::vector<std::string>& run_controls);

// load_checkpoint, except that an unreadable checkpoint is renamed to `<path>.corrupt`
// (replacing an older one), said on stderr, and nothing is returned: the pull starts over, so a
// retry always makes progress.
std::optional<Checkpoint> load_checkpoint_or_move_aside(const std::string& path, const Bed& bed,
                                                        const Parameters& now,
                                                        const std::vector<std::string>& run_controls);

}  // namespace granudrag
