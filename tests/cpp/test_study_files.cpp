// The files of a study: parameters stored by key and read back, bed, run and checkpoint files
// with their provenance, beds of format version 1 still pulled from, and checkpoints refused
// when written with other options or for another bed, naming the difference.
#include <gtest/gtest.h>
#include <hdf5.h>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "contact/contact_keys.hpp"
#include "core/parameters.hpp"
#include "io/file_header.hpp"
#include "io/h5_file.hpp"
#include "io/parameter_record.hpp"
#include "io/run_files.hpp"
#include "io_test_support.hpp"

using namespace granudrag;
using namespace granudrag::support;

namespace {

using Type = ParameterSpec::Type;

ParameterSpec spec(const std::string& key, Type type, const std::string& unit,
                   const std::string& default_value) {
  ParameterSpec s;
  s.key = key;
  s.type = type;
  s.unit = unit;
  s.default_value = default_value;
  s.help = key;
  return s;
}

// A pull-like command with a key of every type, one without a default, and the run controls.
Parameters pull_parameters(const std::vector<std::string>& args = {}) {
  Parameters p("pull",
               {spec("bed", Type::Text, "", "bed.h5"), spec("speed", Type::Number, "sqrt(g d)", "0.5"),
                spec("snapshots", Type::Integer, "", "2"), spec("fresh_start", Type::Flag, "", "false"),
                spec("speeds", Type::NumberList, "sqrt(g d)", "0.1,1"), spec("froude", Type::Number, "", ""),
                spec("threads", Type::Integer, "", "0"), spec("quiet", Type::Flag, "", "true")});
  p.apply_cli(args);
  return p;
}

Parameters pour_parameters() {
  return Parameters("pour", {spec("lx", Type::Number, "d", "5"), spec("ly", Type::Number, "d", "4.5"),
                             spec("grains", Type::Integer, "", "150")});
}

// One shared small bed: 150 soft grains, D = 1.5 at depth 1.5, settled for half a time unit only.
const Bed& tiny_bed() {
  static const Bed bed = [] {
    PourSpec s;
    s.lx = 5;
    s.ly = 4.5;
    s.grains = 150;
    s.intruder_diameter = 1.5;
    s.intruder_x = 2.5;
    s.intruder_y = 2.25;
    s.depth = 1.5;
    s.contact = ContactParams{}.with_stiffness(2e4);
    s.ke_threshold = 1e-2;
    s.max_settle_time = 0.5;
    s.check_interval = 0.25;
    return pour(s, false);
  }();
  return bed;
}

std::unique_ptr<Pull> short_pull(const Bed& bed) {
  PullSpec s;
  s.distance = 0.1;
  auto pull = std::make_unique<Pull>(bed, s);
  pull->run(false);
  return pull;
}

// A bed file as granudrag 0.1 wrote it (format version 1): the parameters as one YAML text.
void write_version_1_bed(const std::string& path, const Bed& bed) {
  h5::File f = h5::File::create(path);
  h5::write_h5md_header(f, "0.1.0 (old)");
  f.set_attr("/granudrag", "format", "granudrag-bed");
  f.set_attr("/granudrag", "version", 1);
  f.set_attr("/parameters", "yaml", "lx: 5.0\nly: 4.5\ngrains: 150\n");
  write_bed_groups(f, bed);
  f.commit();
}

}  // namespace

TEST(ParameterRecord, EveryTypeRoundTripsWithItsUnitAndUnsetKeysAreAbsent) {
  TempDir dir;
  const Parameters par = pull_parameters({"--speed", "0.7", "--speeds", "0.25,2,1e-3", "--fresh_start"});
  const ParameterRecord written = ParameterRecord::of(par);
  EXPECT_EQ(written.find("froude"), nullptr);  // no default, not given
  {
    h5::File f = h5::File::create(dir.file("p.h5"));
    write_parameters(f, written);
    f.commit();
  }
  const h5::File f = h5::File::open(dir.file("p.h5"));
  // Typed attributes, as any HDF5 reader sees them.
  EXPECT_EQ(f.get_attr_double("/parameters/pull", "speed"), 0.7);
  EXPECT_EQ(f.get_attr_int64("/parameters/pull", "snapshots"), 2);
  EXPECT_EQ(f.get_attr_string("/parameters/pull", "bed"), "bed.h5");
  EXPECT_TRUE(f.get_attr_flag("/parameters/pull", "fresh_start"));
  EXPECT_EQ(f.get_attr_doubles("/parameters/pull", "speeds"), (std::vector<double>{0.25, 2, 1e-3}));
  EXPECT_FALSE(f.has_attr("/parameters/pull", "froude"));
  EXPECT_EQ(f.get_attr_string("/parameters/pull/units", "speed"), "sqrt(g d)");
  EXPECT_FALSE(f.has_attr("/parameters/pull/units", "snapshots"));  // dimensionless
  EXPECT_FALSE(f.has_attr("/parameters", "yaml"));

  const ParameterRecord read = read_parameters(f, "pull");
  ASSERT_EQ(read.values.size(), written.values.size());
  for (const RecordedParameter& w : written.values) {
    const RecordedParameter* r = read.find(w.key);
    ASSERT_NE(r, nullptr) << w.key;
    EXPECT_TRUE(r->same_value(w)) << w.key << ": " << r->value_text() << " vs " << w.value_text();
    EXPECT_EQ(r->unit, w.unit) << w.key;
  }
  EXPECT_EQ(read.find("speeds")->value_text(), "[0.25, 2, 0.001]");
  EXPECT_EQ(read.find("bed")->value_text(), "\"bed.h5\"");
  EXPECT_EQ(read.find("fresh_start")->value_text(), "true");
}

TEST(ParameterRecord, DifferencesNameEachKeyBothWays) {
  const ParameterRecord then = ParameterRecord::of(pull_parameters({"--threads", "2"}));
  EXPECT_EQ(describe_differences(then, then, {}, "checkpoint", "now"), "");
  const ParameterRecord now = ParameterRecord::of(pull_parameters({"--speed", "0.7", "--froude", "1.5"}));
  EXPECT_EQ(describe_differences(then, now, {"threads"}, "checkpoint", "now"),
            "\n  checkpoint: speed: 0.5\n  now:        speed: 0.7"
            "\n  checkpoint: froude: ~\n  now:        froude: 1.5");
  EXPECT_MENTIONS(describe_differences(then, now, {}, "checkpoint", "now"), "threads: 2");
}

TEST(ParameterRecord, AnAttributeNoKeyCanHoldIsRefusedByName) {
  TempDir dir;
  {
    h5::File f = h5::File::create(dir.file("odd.h5"));
    f.set_attr("/parameters/pull", "speed", 1.0);
    f.set_attr("/parameters/pull", "ids", std::vector<std::int64_t>{1, 2});
    f.commit();
  }
  const h5::File f = h5::File::open(dir.file("odd.h5"));
  const std::string message = error_of([&] { read_parameters(f, "pull"); });
  EXPECT_MENTIONS(message, "'ids'");
  EXPECT_MENTIONS(message, "odd.h5");
  EXPECT_MENTIONS(error_of([&] { read_parameters(f, "pour"); }), "/parameters/pour");
}

TEST(BedFile, CarriesItsParametersAndOldVersionsStillLoad) {
  TempDir dir;
  const Bed& bed = tiny_bed();
  save_bed(dir.file("bed.h5"), bed, pour_parameters());
  ParameterRecord parameters;
  const Bed loaded = load_bed(dir.file("bed.h5"), &parameters);
  EXPECT_EQ(loaded.state.particles.x, bed.state.particles.x);
  EXPECT_EQ(parameters.command, "pour");
  ASSERT_NE(parameters.find("grains"), nullptr);
  EXPECT_EQ(parameters.find("grains")->integer, 150);
  EXPECT_EQ(h5::File::open(dir.file("bed.h5")).get_attr_int64("/granudrag", "version"), kFileVersion);

  write_version_1_bed(dir.file("old.h5"), bed);
  const Bed old = load_bed(dir.file("old.h5"), &parameters);
  EXPECT_EQ(old.state.particles.x, bed.state.particles.x);
  EXPECT_TRUE(parameters.values.empty());
  EXPECT_EQ(parameters.legacy_yaml, "lx: 5.0\nly: 4.5\ngrains: 150\n");

  {
    h5::File f = h5::File::create(dir.file("future.h5"));
    f.set_attr("/granudrag", "format", "granudrag-bed");
    f.set_attr("/granudrag", "version", 99);
    f.commit();
  }
  const std::string future = error_of([&] { load_bed(dir.file("future.h5")); });
  EXPECT_MENTIONS(future, "format version 99");
  EXPECT_MENTIONS(future, "versions 1 to " + std::to_string(kFileVersion));
  EXPECT_MENTIONS(future, "future.h5");
}

TEST(BedFile, CarriesEveryContactField) {
  // The pull's contact law is the bed's: each field bound to a contact key is written and read
  // back, a new key's included (bed_file.cpp takes them from the key table).
  TempDir dir;
  Bed bed = tiny_bed();
  int i = 0;
  for (const auto& row : contact_keys().rows())
    if (row.set_number) row.set_number(bed.contact, *row.number(bed.contact) + 0.01 * ++i);
  save_bed(dir.file("bed.h5"), bed, pour_parameters());
  const Bed loaded = load_bed(dir.file("bed.h5"));
  for (const auto& row : contact_keys().rows())
    if (row.number) {
      EXPECT_EQ(*row.number(loaded.contact), *row.number(bed.contact)) << row.spec.key;
    }
  EXPECT_GT(i, 4);
}

TEST(RunFile, CarriesTheBedsParametersAndThePulls) {
  TempDir dir;
  const Bed& bed = tiny_bed();
  const auto pull_ptr = short_pull(bed);
  const Pull& pull = *pull_ptr;
  save_run(dir.file("run.h5"), pull, pull_parameters(), ParameterRecord::of(pour_parameters()), "sanity\n");
  {
    const h5::File f = h5::File::open(dir.file("run.h5"));
    EXPECT_EQ(f.get_attr_string("/granudrag", "format"), "granudrag-run");
    EXPECT_EQ(f.get_attr_double("/parameters/pour", "lx"), 5.0);
    EXPECT_EQ(f.get_attr_int64("/parameters/pour", "grains"), 150);
    EXPECT_EQ(f.get_attr_double("/parameters/pull", "speed"), 0.5);
    EXPECT_TRUE(f.attr_names("/parameters").empty());  // no YAML text
  }
  // Pulled from a bed of format version 1: its text is carried for people, not as keys.
  write_version_1_bed(dir.file("old.h5"), bed);
  ParameterRecord old;
  load_bed(dir.file("old.h5"), &old);
  save_run(dir.file("run_old.h5"), pull, pull_parameters(), old, "sanity\n");
  const h5::File f = h5::File::open(dir.file("run_old.h5"));
  EXPECT_FALSE(f.exists("/parameters/pour"));
  EXPECT_EQ(f.get_attr_string("/parameters", "pour_yaml_v1"), old.legacy_yaml);
  EXPECT_EQ(f.get_attr_double("/parameters/pull", "speed"), 0.5);
}

// A placed bed's run says so: the pull copies the bed's /parameters/place beside its pour's.
TEST(RunFile, CarriesAPlacedBedsPlacement) {
  TempDir dir;
  const Bed& bed = tiny_bed();
  const Parameters place(
      "place", {spec("depth", Type::Number, "d", "3"), spec("settle_damping", Type::Number, "", "1")});
  save_placed_bed(dir.file("placed.h5"), bed, ParameterRecord::of(pour_parameters()), place, "column.h5",
                  PlacementRecord{});
  ParameterRecord pour, placement;
  load_bed(dir.file("placed.h5"), &pour, &placement);
  EXPECT_EQ(pour.command, "pour");
  ASSERT_EQ(placement.command, "place");
  const auto pull_ptr = short_pull(bed);
  save_run(dir.file("run.h5"), *pull_ptr, pull_parameters(), pour, "sanity\n", nullptr, &placement);
  {
    const h5::File f = h5::File::open(dir.file("run.h5"));
    EXPECT_EQ(f.get_attr_double("/parameters/place", "depth"), 3.0);
    EXPECT_EQ(f.get_attr_double("/parameters/pour", "lx"), 5.0);
  }
  // A poured bed has none, and its run no /parameters/place.
  save_bed(dir.file("poured.h5"), bed, pour_parameters());
  load_bed(dir.file("poured.h5"), &pour, &placement);
  EXPECT_TRUE(placement.command.empty());
  save_run(dir.file("run_poured.h5"), *pull_ptr, pull_parameters(), pour, "sanity\n", nullptr, &placement);
  EXPECT_FALSE(h5::File::open(dir.file("run_poured.h5")).exists("/parameters/place"));
}

TEST(CheckpointFile, ResumesOnlyWithTheSameOptionsAndBed) {
  TempDir dir;
  const Bed& bed = tiny_bed();
  const auto pull_ptr = short_pull(bed);
  const Pull& pull = *pull_ptr;
  const std::string path = dir.file("run.h5.checkpoint.h5");
  const std::vector<std::string> controls = {"threads", "quiet"};
  save_checkpoint(path, pull, pull_parameters({"--threads", "2"}), ParameterRecord::of(pour_parameters()));

  const Checkpoint c = load_checkpoint(path, bed, pull_parameters({"--quiet", "false"}), controls);
  EXPECT_EQ(c.state.steps, pull.state().steps);
  EXPECT_EQ(c.record.fx, pull.record().fx);
  EXPECT_EQ(h5::File::open(path).get_attr_int64("/parameters/pour", "grains"), 150);

  const std::string other = error_of([&] {
    load_checkpoint(path, bed, pull_parameters({"--speed", "0.7"}), controls);
  });
  EXPECT_MENTIONS(other, "checkpoint: speed: 0.5\n  now:        speed: 0.7");
  EXPECT_MENTIONS(other, path);
  EXPECT_MENTIONS(other, "delete the checkpoint");

  Bed moved = bed;  // same size, box and contact law: only the fingerprint tells them apart
  moved.state.particles.x[0].x() += 1e-9;
  const std::string another = error_of([&] { load_checkpoint(path, moved, pull_parameters(), controls); });
  EXPECT_MENTIONS(another, "bed_fingerprint");

  {
    h5::File f = h5::File::create(dir.file("v1.checkpoint.h5"));
    f.set_attr("/granudrag", "format", "granudrag-checkpoint");
    f.set_attr("/granudrag", "version", 1);
    f.commit();
  }
  const std::string old =
      error_of([&] { load_checkpoint(dir.file("v1.checkpoint.h5"), bed, pull_parameters(), controls); });
  EXPECT_MENTIONS(old, "format version 1");
  EXPECT_MENTIONS(old, "delete it to start the pull over");
}

TEST(CheckpointFile, ACheckpointWrittenBeforeThetasSeriesResumesWithItsTotalsAsTheBaseline) {
  TempDir dir;
  const Bed& bed = tiny_bed();
  const auto pull_ptr = short_pull(bed);
  const Pull& pull = *pull_ptr;
  const std::string path = dir.file("run.h5.checkpoint.h5");
  save_checkpoint(path, pull, pull_parameters(), ParameterRecord::of(pour_parameters()));
  const std::vector<std::string> controls = {"threads", "quiet"};
  EXPECT_EQ(load_checkpoint(path, bed, pull_parameters(), controls).record.theta_count_series,
            pull.record().theta_count_series);
  EXPECT_EQ(load_checkpoint(path, bed, pull_parameters(), controls).record.theta_present_sum,
            pull.record().theta_present_sum);
  {
    const hid_t f = H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    ASSERT_GE(H5Ldelete(f, "/pull/theta_sum_series", H5P_DEFAULT), 0);
    ASSERT_GE(H5Ldelete(f, "/pull/theta_count_series", H5P_DEFAULT), 0);
    ASSERT_GE(H5Ldelete(f, "/pull/theta_present_sum", H5P_DEFAULT), 0);
    ASSERT_GE(H5Ldelete(f, "/pull/theta_present_count", H5P_DEFAULT), 0);
    H5Fclose(f);
  }
  const Checkpoint c = load_checkpoint(path, bed, pull_parameters(), controls);
  EXPECT_TRUE(c.record.theta_sum_series.empty());  // read as written: no series
  ASSERT_FALSE(c.record.time.empty());
  // The resumed pull takes the totals so far as the baseline of the intervals to come.
  const Pull resumed(bed, pull.spec(), c.state, c.record);
  const PullRecord& r = resumed.record();
  ASSERT_EQ(r.theta_sum_series.size(), r.time.size());
  ASSERT_EQ(r.theta_count_series.size(), r.time.size());
  for (std::size_t k = 0; k + 1 < r.time.size(); ++k) EXPECT_TRUE(std::isnan(r.theta_sum_series[k])) << k;
  EXPECT_EQ(r.theta_sum_series.back(), pull.record().theta_sum);
  EXPECT_EQ(r.theta_count_series.back(), static_cast<double>(pull.record().theta_count));
  // The present contacts' series of those intervals are unknown: NaN, left out of its mean.
  ASSERT_EQ(r.theta_present_sum.size(), r.time.size());
  for (double s : r.theta_present_sum) EXPECT_TRUE(std::isnan(s));
}
