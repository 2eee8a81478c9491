#include "io/checkpoint_file.hpp"

#include <cstdio>

#include "core/error.hpp"
#include "io/bed_file.hpp"
#include "io/file_header.hpp"
#include "io/particle_data.hpp"

namespace granudrag {

namespace {

const char* kCheckpointFormat = "granudrag-checkpoint";
// The order of the bodies in a checkpoint's state: the simulation's spatial order (Pull::order()).
// Checkpoints written before pulls stepped their bodies in it hold the bed's order and lack this
// attribute; such a checkpoint is moved aside and its pull starts over.
const char* kBodyOrder = "spatial";

void write_pull_record(h5::File& f, const PullRecord& r) {
  f.set_attr("/pull", "samples_per_interval", static_cast<std::int64_t>(r.samples_per_interval));
  f.set_attr("/pull", "total_steps", static_cast<std::int64_t>(r.total_steps));
  f.write("/pull/time", r.time);
  f.write("/pull/fx", r.fx);
  f.write("/pull/fy", r.fy);
  f.write("/pull/fz", r.fz);
  f.write("/pull/contacts", r.contacts);
  // One entry (older checkpoints carry a second, the squares' sum the error no longer uses).
  f.write("/pull/theta_sums", std::vector<double>{r.theta_sum});
  f.set_attr("/pull", "theta_count", static_cast<std::int64_t>(r.theta_count));
  f.write("/pull/theta_histogram",
          std::vector<std::int64_t>(r.theta_histogram.begin(), r.theta_histogram.end()));
  f.write("/pull/theta_sum_series", r.theta_sum_series);
  f.write("/pull/theta_count_series", r.theta_count_series);
  f.write("/pull/theta_present_sum", r.theta_present_sum);
  f.write("/pull/theta_present_count", r.theta_present_count);
  f.write("/pull/z_histogram", std::vector<std::int64_t>(r.z_histogram.begin(), r.z_histogram.end()));
  f.write("/pull/shell_grains", std::vector<std::int64_t>(r.shells.grains.begin(), r.shells.grains.end()));
  f.write("/pull/shell_contacts",
          std::vector<std::int64_t>(r.shells.contacts.begin(), r.shells.contacts.end()));
  f.write("/pull/energy", std::vector<double>{r.work, r.max_overlap, r.energy_start, r.contact_sum});
  f.write_rows("/pull/force_sum", std::vector<Vec3>{r.force_sum});
  f.set_attr("/pull", "grains_lost", static_cast<std::int64_t>(r.grains_lost));
  f.set_attr("/pull", "verdict", r.verdict);
  f.set_attr("/pull", "frames", static_cast<std::int64_t>(r.frames));
  f.set_attr("/pull", "snapshots", static_cast<std::int64_t>(r.snapshots.size()));
  write_snapshots(f, "/pull/snapshot_", r.snapshots);
  if (!r.sleeping.empty()) f.write("/pull/sleeping", r.sleeping);
}

// The active region's state (engine/active_region.hpp), when the pull has one.
void write_region(h5::File& f, const ActiveRegion::State& s) {
  if (s.held.empty()) return;
  f.write("/active_region/held", s.held);
  f.write("/active_region/at_rest", std::vector<int>(s.at_rest.begin(), s.at_rest.end()));
  f.write_rows("/active_region/anchor", s.anchor);
  f.write_rows("/active_region/force_sum", s.force_sum);
  f.write_rows("/active_region/held_force", s.held_force);
  if (!s.held_load.empty()) f.write("/active_region/held_load", s.held_load);
  f.write_rows("/active_region/reference", s.reference);
  f.write("/active_region/reference_due", s.reference_due);
  f.write("/active_region/quiet", s.quiet);
  f.write("/active_region/counters", std::vector<std::int64_t>{s.interval_steps, s.wake_ups, s.sleeps});
}

ActiveRegion::State read_region(const h5::File& f) {
  ActiveRegion::State s;
  if (!f.exists("/active_region/held")) return s;
  s.held = f.read_uint8("/active_region/held");
  const std::vector<int> at_rest = f.read_ints("/active_region/at_rest");
  s.at_rest.assign(at_rest.begin(), at_rest.end());
  s.anchor = f.read_vec3("/active_region/anchor");
  s.force_sum = f.read_vec3("/active_region/force_sum");
  s.held_force = f.read_vec3("/active_region/held_force");
  if (f.exists("/active_region/held_load")) s.held_load = f.read_doubles("/active_region/held_load");
  s.reference = f.read_vec3("/active_region/reference");
  s.reference_due = f.read_uint8("/active_region/reference_due");
  // Written before quiet grains were skipped: none quiet, every held grain stepped (the same
  // physics; the first check that changes the held set finds the quiet ones).
  if (f.exists("/active_region/quiet"))
    s.quiet = f.read_uint8("/active_region/quiet");
  else
    s.quiet.assign(s.held.size(), 0);
  const std::vector<std::int64_t> counters = f.read_int64("/active_region/counters");
  s.interval_steps = counters.at(0);
  s.wake_ups = counters.at(1);
  s.sleeps = counters.at(2);
  return s;
}

PullRecord read_pull_record(const h5::File& f) {
  PullRecord r;
  r.samples_per_interval = f.get_attr_int64("/pull", "samples_per_interval");
  if (r.samples_per_interval < 1) throw Error("samples_per_interval < 1 under /pull");
  r.total_steps = f.get_attr_int64("/pull", "total_steps");
  r.time = f.read_doubles("/pull/time");
  r.fx = f.read_doubles("/pull/fx");
  r.fy = f.read_doubles("/pull/fy");
  r.fz = f.read_doubles("/pull/fz");
  r.contacts = f.read_doubles("/pull/contacts");
  const auto theta = f.read_doubles("/pull/theta_sums");
  r.theta_sum = theta.at(0);
  r.theta_count = f.get_attr_int64("/pull", "theta_count");
  const auto th = f.read_int64("/pull/theta_histogram");
  r.theta_histogram.assign(th.begin(), th.end());
  if (f.exists("/pull/theta_sum_series")) {
    r.theta_sum_series = f.read_doubles("/pull/theta_sum_series");
    r.theta_count_series = f.read_doubles("/pull/theta_count_series");
    if (r.theta_sum_series.size() != r.time.size() || r.theta_count_series.size() != r.time.size())
      throw Error("/pull/theta_sum_series or /pull/theta_count_series is not as long as /pull/time");
  }  // else written before the series: the resumed Pull takes its totals as the baseline
  if (f.exists("/pull/theta_present_sum")) {
    r.theta_present_sum = f.read_doubles("/pull/theta_present_sum");
    r.theta_present_count = f.read_doubles("/pull/theta_present_count");
    if (r.theta_present_sum.size() != r.time.size() || r.theta_present_count.size() != r.time.size())
      throw Error("/pull/theta_present_sum or /pull/theta_present_count is not as long as /pull/time");
  }  // else written before the series: the resumed Pull marks its intervals unknown (NaN)
  const auto zh = f.read_int64("/pull/z_histogram");
  r.z_histogram.assign(zh.begin(), zh.end());
  // Checkpoints written before the shells have none: counted from the resume on.
  if (f.exists("/pull/shell_grains")) {
    const auto sg = f.read_int64("/pull/shell_grains");
    const auto sc = f.read_int64("/pull/shell_contacts");
    if (sg.size() != r.shells.grains.size() || sc.size() != r.shells.contacts.size())
      throw Error("/pull/shell_grains or /pull/shell_contacts has the wrong length");
    r.shells.grains.assign(sg.begin(), sg.end());
    r.shells.contacts.assign(sc.begin(), sc.end());
  }
  const auto en = f.read_doubles("/pull/energy");
  r.work = en.at(0);
  r.max_overlap = en.at(1);
  r.energy_start = en.at(2);
  r.contact_sum = en.at(3);
  r.force_sum = f.read_vec3("/pull/force_sum").at(0);
  // Checkpoints written before the run guard have neither: clean so far.
  if (f.has_attr("/pull", "grains_lost")) r.grains_lost = f.get_attr_int64("/pull", "grains_lost");
  if (f.has_attr("/pull", "verdict")) r.verdict = f.get_attr_string("/pull", "verdict");
  if (f.has_attr("/pull", "frames")) r.frames = f.get_attr_int64("/pull", "frames");
  if (r.frames < 0) throw Error("negative frame count under /pull");
  const std::int64_t ns = f.get_attr_int64("/pull", "snapshots");
  if (ns < 0) throw Error("negative snapshot count under /pull");
  r.snapshots = read_snapshots(f, "/pull/snapshot_", static_cast<std::size_t>(ns));
  if (f.exists("/pull/sleeping")) r.sleeping = f.read_doubles("/pull/sleeping");
  return r;
}

}  // namespace

std::string bed_fingerprint(const Bed& bed) {
  std::uint64_t h = 1469598103934665603ull;  // FNV-1a over the bytes
  auto mix = [&h](const void* data, std::size_t bytes) {
    const auto* b = static_cast<const unsigned char*>(data);
    for (std::size_t k = 0; k < bytes; ++k) h = (h ^ b[k]) * 1099511628211ull;
  };
  const Particles& p = bed.state.particles;
  mix(p.x.data(), p.x.size() * sizeof(Vec3));
  mix(p.radius.data(), p.radius.size() * sizeof(double));
  mix(p.species.data(), p.species.size() * sizeof(Species));
  char text[32];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(h));
  return text;
}

void save_checkpoint(const std::string& path, const Pull& pull, const Parameters& pull_parameters,
                     const ParameterRecord& bed_parameters) {
  h5::File f = h5::File::create(path, h5::Compression::None);
  write_file_header(f, kCheckpointFormat);
  write_parameters(f, bed_parameters);
  write_parameters(f, ParameterRecord::of(pull_parameters));
  f.set_attr("/pull", "bed_fingerprint", bed_fingerprint(pull.bed()));
  f.set_attr("/pull", "body_order", std::string(kBodyOrder));
  Bed bed = pull.bed();
  bed.state = pull.state();  // in the simulation's order (Pull::order())
  bed.intruder = pull.intruder();
  write_bed_groups(f, bed);
  write_region(f, bed.state.region);
  write_pull_record(f, pull.record());
  f.commit();
}

Checkpoint load_checkpoint(const std::string& path, const Bed& bed, const Parameters& now,
                           const std::vector<std::string>& run_controls) {
  Checkpoint c;
  std::string differences;
  bool other_bed = false;  // readable, but not this pull's: an Error, not UnreadableCheckpoint
  try {
    const h5::File f = h5::File::open(path);
    check_file_header(f, kCheckpointFormat, 2, "delete it to start the pull over");
    if (!f.has_attr("/pull", "body_order") || f.get_attr_string("/pull", "body_order") != kBodyOrder)
      throw Error(
          "its bodies are in the bed's order (written by a granudrag before pulls stepped them in a "
          "spatial order)");
    Bed saved;
    try {
      saved = read_bed_groups(f);
      c.state = saved.state;
      c.state.region = read_region(f);
      c.record = read_pull_record(f);
    } catch (const Error& e) {
      throw Error(std::string("it cannot be read: ") + e.what());
    }
    other_bed = saved.state.particles.size() != bed.state.particles.size() || saved.box.lx != bed.box.lx ||
                saved.contact.kn != bed.contact.kn || saved.dt != bed.dt;
    if (other_bed)
      throw Error("checkpoint '" + path +
                  "' cannot be used: it belongs to another bed (particle count, box, stiffness or time step "
                  "differ); delete it to start the pull over");
    const ParameterRecord then = read_parameters(f, "pull");
    differences = describe_differences(then, ParameterRecord::of(now), run_controls, "checkpoint", "now");
    const std::string saved_bed = f.get_attr_string("/pull", "bed_fingerprint");
    const std::string this_bed = bed_fingerprint(bed);
    if (saved_bed != this_bed)
      differences +=
          "\n  checkpoint: bed_fingerprint: " + saved_bed + "\n  now:        bed_fingerprint: " + this_bed;
  } catch (const std::out_of_range&) {
    throw UnreadableCheckpoint("checkpoint '" + path + "' is damaged (short arrays under /pull)");
  } catch (const Error& e) {
    if (other_bed) throw;
    throw UnreadableCheckpoint("checkpoint '" + path + "' cannot be used: " + e.what());
  }
  if (!differences.empty())
    throw Error("checkpoint '" + path + "' was written by a pull with other options or another bed:" +
                differences + "\nrerun with the same options, or delete the checkpoint to start over");
  return c;
}

std::optional<Checkpoint> load_checkpoint_or_move_aside(const std::string& path, const Bed& bed,
                                                        const Parameters& now,
                                                        const std::vector<std::string>& run_controls) {
  return load_or_move_aside(path, [&] { return load_checkpoint(path, bed, now, run_controls); });
}

}  // namespace granudrag
