#include "io/pour_checkpoint.hpp"

#include <stdexcept>

#include "core/error.hpp"
#include "io/file_header.hpp"
#include "io/parameter_record.hpp"
#include "io/particle_data.hpp"
#include "io/unreadable_checkpoint.hpp"

namespace granudrag {

namespace {
const char* kPourCheckpointFormat = "granudrag-pour-checkpoint";
}

void save_pour_checkpoint(const std::string& path, const Pour& pour, const Parameters& pour_parameters) {
  const PourRecord& r = pour.record();
  h5::File f = h5::File::create(path, h5::Compression::None);
  write_file_header(f, kPourCheckpointFormat);
  write_parameters(f, ParameterRecord::of(pour_parameters));
  write_particle_state(f, pour.state(), pour.simulation().dt());
  f.set_attr("/pour", "energy_start", r.energy_start);
  f.set_attr("/pour", "max_overlap_seen", r.max_overlap);
  f.set_attr("/pour", "grains_lost", static_cast<std::int64_t>(r.grains_lost));
  f.set_attr("/pour", "frames", static_cast<std::int64_t>(r.frames));
  f.commit();
}

PourCheckpoint load_pour_checkpoint(const std::string& path, const Parameters& now,
                                    const std::vector<std::string>& run_controls) {
  PourCheckpoint c;
  PourRecord& s = c.record;
  std::string differences;
  try {
    const h5::File f = h5::File::open(path);
    check_file_header(f, kPourCheckpointFormat, 2, "delete it to start the pour over");
    c.state = read_particle_state(f);
    s.energy_start = f.get_attr_double("/pour", "energy_start");
    s.max_overlap = f.get_attr_double("/pour", "max_overlap_seen");
    s.grains_lost = f.get_attr_int64("/pour", "grains_lost");
    if (f.has_attr("/pour", "frames")) s.frames = f.get_attr_int64("/pour", "frames");
    if (s.frames < 0) throw Error("negative frame count under /pour");
    const ParameterRecord then = read_parameters(f, "pour");
    differences = describe_differences(then, ParameterRecord::of(now), run_controls, "checkpoint", "now");
  } catch (const std::out_of_range&) {
    throw UnreadableCheckpoint("checkpoint '" + path + "' is damaged (short arrays)");
  } catch (const Error& e) {
    throw UnreadableCheckpoint("checkpoint '" + path + "' cannot be used: " + e.what());
  }
  if (!differences.empty())
    throw Error("checkpoint '" + path + "' was written by a pour with other options:" + differences +
                "\nrerun with the same options, or delete the checkpoint to start over");
  return c;
}

std::optional<PourCheckpoint> load_pour_checkpoint_or_move_aside(
    const std::string& path, const Parameters& now, const std::vector<std::string>& run_controls) {
  return load_or_move_aside(path, [&] { return load_pour_checkpoint(path, now, run_controls); });
}

}  // namespace granudrag
