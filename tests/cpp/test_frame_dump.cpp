// Frames of a run (io/frame_dump.hpp): what is added is what the output file holds, a resumed
// dump keeps the sealed frames and drops the rest, missing frames are an error naming the
// file, and the temporal XDMF sidecar describes every frame.
#include <gtest/gtest.h>

#include <filesystem>
#include <regex>

#include "io/frame_dump.hpp"
#include "io/xdmf.hpp"
#include "io_test_support.hpp"

using namespace granudrag;
using namespace granudrag::support;
namespace fs = std::filesystem;

namespace {

Particles bodies(std::size_t n) {
  Particles p;
  for (std::size_t i = 0; i < n; ++i)
    p.add(Vec3(0.5 + i, 0.25 * i, 1.0), 0.5, i == 0 ? Species::Frozen : Species::Mobile);
  p.add(Vec3(3, 3, 3), 1.0, Species::Intruder);
  return p;
}

// The bodies at frame k: every coordinate and velocity depends on k and the body.
void move_to_frame(Particles& p, long k) {
  for (std::size_t i = 0; i < p.size(); ++i) {
    p.x[i] = Vec3(0.5 + i + 0.01 * k, 0.25 * i, 1.0 + 1e-3 * k * i);
    p.v[i] = Vec3(k, -static_cast<double>(i), 0.5 * k);
  }
}

void add_frames(FrameDump& dump, Particles& p, long from, long to) {
  for (long k = from; k < to; ++k) {
    move_to_frame(p, k);
    dump.add(10 * k, 0.1 * k, p);
  }
}

// Writes the dump into `path` and checks that it holds frames 0 .. frames-1 as move_to_frame.
void expect_frames(FrameDump& dump, const std::string& path, Particles p, long frames) {
  {
    h5::File f = h5::File::create(path);
    dump.write_into(f);
    f.commit();
  }
  const h5::File f = h5::File::open(path);
  for (const char* element : {"position", "velocity"}) {
    const h5::SeriesData d = f.read_series(std::string("/particles/frames/") + element);
    ASSERT_EQ(d.rows(), static_cast<std::size_t>(frames)) << element;
    EXPECT_EQ(d.row_shape, (std::vector<std::size_t>{p.size(), 3})) << element;
    for (long k = 0; k < frames; ++k) {
      EXPECT_EQ(d.steps[k], 10 * k);
      EXPECT_EQ(d.times[k], 0.1 * k);
      move_to_frame(p, k);
      const auto& want = element == std::string("position") ? p.x : p.v;
      for (std::size_t i = 0; i < p.size(); ++i)
        for (int c = 0; c < 3; ++c)
          ASSERT_EQ(d.values[k * d.columns + 3 * i + c], want[i][c]) << element << k << i;
    }
  }
  EXPECT_EQ(f.read_uint8("/particles/frames/species/value"), (std::vector<std::uint8_t>{1, 0, 0, 0, 2}));
  EXPECT_EQ(f.read_doubles("/particles/frames/radius/value"), p.radius);
}

}  // namespace

TEST(FrameDump, TheOutputHoldsEveryFrameAddedAndTheSegmentsGoAfterwards) {
  TempDir dir;
  const std::string out = dir.file("run.h5");
  Particles p = bodies(4);
  FrameDump dump(out, p, 0);
  add_frames(dump, p, 0, 3);
  dump.seal();  // a checkpoint: frames 0-2 in a sealed segment
  add_frames(dump, p, 3, 7);
  EXPECT_EQ(dump.frames(), 7);
  expect_frames(dump, out, bodies(4), 7);
  EXPECT_EQ(FrameDump::segments_of(out).size(), 2u);
  dump.remove_segments();
  EXPECT_TRUE(FrameDump::segments_of(out).empty());
  for (const auto& e : fs::directory_iterator(dir.path()))
    EXPECT_EQ(e.path().filename(), "run.h5") << "left behind: " << e.path();
}

TEST(FrameDump, AResumedDumpKeepsTheSealedFramesAndWritesTheRestAgain) {
  TempDir dir;
  const std::string out = dir.file("run.h5");
  Particles p = bodies(4);
  {
    FrameDump dump(out, p, 0);
    add_frames(dump, p, 0, 3);
    dump.seal();
    add_frames(dump, p, 3, 5);  // then killed: frames 3 and 4 were never sealed
    dump.seal();                // ... or sealed after the checkpoint that counts 3 was saved
  }
  ASSERT_EQ(FrameDump::segments_of(out).size(), 2u);
  FrameDump resumed(out, p, 3);  // the checkpoint counts 3 frames
  EXPECT_EQ(resumed.frames(), 3);
  EXPECT_EQ(FrameDump::segments_of(out).size(), 1u);
  add_frames(resumed, p, 3, 6);
  expect_frames(resumed, out, bodies(4), 6);
}

TEST(FrameDump, AFreshRunRemovesAnEarlierRunsSegments) {
  TempDir dir;
  const std::string out = dir.file("run.h5");
  Particles p = bodies(4);
  {
    FrameDump dump(out, p, 0);
    add_frames(dump, p, 0, 2);
    dump.seal();
  }
  FrameDump fresh(out, p, 0);
  EXPECT_TRUE(FrameDump::segments_of(out).empty());
  add_frames(fresh, p, 0, 1);
  expect_frames(fresh, out, bodies(4), 1);
}

TEST(FrameDump, MissingFramesAreAnErrorNamingTheSegment) {
  TempDir dir;
  const std::string out = dir.file("run.h5");
  Particles p = bodies(4);
  {
    FrameDump dump(out, p, 0);
    add_frames(dump, p, 0, 2);
    dump.seal();
    add_frames(dump, p, 2, 4);
    dump.seal();
  }
  fs::remove(FrameDump::segments_of(out).at(0).path);
  const std::string e = error_of([&] { FrameDump d(out, p, 4); });
  EXPECT_NE(e.find("counts 4 frames"), std::string::npos) << e;
  EXPECT_NE(e.find("run.h5.frames.00000000.h5' is missing"), std::string::npos) << e;
  EXPECT_NE(e.find("run.h5.checkpoint.h5' to start the run over"), std::string::npos) << e;
  // Frames of another number of bodies are not this run's.
  const std::string other = dir.file("other.h5");
  {
    FrameDump dump(other, bodies(7), 0);
    Particles q = bodies(7);
    add_frames(dump, q, 0, 1);
    dump.seal();
  }
  const std::string e2 = error_of([&] { FrameDump d(other, p, 1); });
  EXPECT_NE(e2.find("another run"), std::string::npos) << e2;
}

TEST(FrameDump, TheTemporalSidecarDescribesEachFrameAsAHyperslab) {
  TempDir dir;
  const std::string xdmf = dir.file("run.h5.xdmf");
  write_frames_xdmf(xdmf, "run.h5", 5, {0.0, 0.5, 1.25});
  const std::string s = read_text(xdmf);
  EXPECT_NE(s.find("CollectionType=\"Temporal\""), std::string::npos);
  const std::regex time("<Time Value=\"([0-9.e+-]+)\"/>");
  std::vector<std::string> times;
  for (auto it = std::sregex_iterator(s.begin(), s.end(), time); it != std::sregex_iterator(); ++it)
    times.push_back((*it)[1]);
  EXPECT_EQ(times, (std::vector<std::string>{"0", "0.5", "1.25"}));
  // Frame 2 of position and velocity: start (2, 0, 0), count (1, 5, 3) of [3 x 5 x 3].
  EXPECT_EQ(std::count(s.begin(), s.end(), '\n') > 10, true);
  EXPECT_NE(s.find(">2 0 0 1 1 1 1 5 3</DataItem><DataItem Dimensions=\"3 5 3\""), std::string::npos);
  EXPECT_NE(s.find("run.h5:/particles/frames/position/value"), std::string::npos);
  EXPECT_NE(s.find("run.h5:/particles/frames/velocity/value"), std::string::npos);
  EXPECT_NE(s.find("run.h5:/particles/frames/species/value"), std::string::npos);
  EXPECT_NE(error_of([&] { write_frames_xdmf(xdmf, "a:b.h5", 5, {0.0}); }).find("contains ':'"),
            std::string::npos);
  EXPECT_NE(error_of([&] { write_frames_xdmf(xdmf, "run.h5", 5, {}); }).find("no frames"), std::string::npos);
}
