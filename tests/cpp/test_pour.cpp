// Pouring: placement without overlaps, the slab-volume geometry behind the surface definition,
// and a real pour that must settle to a random close packing at the requested depth.
#include <gtest/gtest.h>

#include "core/error.hpp"
#include "helpers.hpp"
#include "protocol/bed_profile.hpp"
#include "protocol/pour.hpp"
#include "protocol/run_report.hpp"

using namespace granudrag;

TEST(BedProfile, SliceVolumesAddUpToTheSphere) {
  const double r = 0.47, zc = 3.123;
  double total = 0;
  for (int k = 0; k < 80; ++k) total += sphere_slice_volume(r, zc, 0.1 * k, 0.1 * (k + 1));
  EXPECT_NEAR(total, 4.0 / 3.0 * M_PI * r * r * r, 1e-12);
  EXPECT_NEAR(sphere_slice_volume(r, zc, zc, 10), 2.0 / 3.0 * M_PI * r * r * r, 1e-12);
  EXPECT_EQ(sphere_slice_volume(r, zc, 0, 1), 0.0);
}

TEST(BedProfile, SurfaceOfAnIdealSlabIsItsTop) {
  // A simple cubic crystal of touching unit spheres, 12 layers: packing pi/6, top at z = 12.
  Particles p;
  for (int iz = 0; iz < 12; ++iz)
    for (int ix = 0; ix < 8; ++ix)
      for (int iy = 0; iy < 8; ++iy) p.add(Vec3(ix + 0.5, iy + 0.5, iz + 0.5), 0.5, Species::Mobile);
  const BedProfile prof = measure_bed(p, Box{8, 8, true});
  EXPECT_NEAR(prof.bulk_packing_fraction, M_PI / 6, 0.08);  // the slab average oscillates
  EXPECT_NEAR(prof.surface_height, 11.5, 0.5);              // half-density point inside the top layer
}

TEST(BedProfile, AGrainInFlightDoesNotMoveTheSurface) {
  Particles p;
  for (int iz = 0; iz < 12; ++iz)
    for (int ix = 0; ix < 8; ++ix)
      for (int iy = 0; iy < 8; ++iy) p.add(Vec3(ix + 0.5, iy + 0.5, iz + 0.5), 0.5, Species::Mobile);
  const double before = measure_bed(p, Box{8, 8, true}).surface_height;
  p.add(Vec3(4, 4, 30), 0.5, Species::Mobile);  // one grain far above the bed
  EXPECT_NEAR(measure_bed(p, Box{8, 8, true}).surface_height, before, 1e-9);
}

TEST(Pour, DoesNotStopBeforeTheGrainsHaveFallen) {
  // A kinetic-energy threshold met at once (grains start at rest) must not end the pour.
  PourSpec s;
  s.lx = s.ly = 8;
  s.intruder_x = s.intruder_y = 4;
  s.grains = 600;
  s.depth = 3;
  s.contact = ContactParams{}.with_stiffness(2e4);
  s.ke_threshold = 1.0;
  s.check_interval = 1e-3;
  s.max_settle_time = 20;
  const Bed bed = pour(s, false);
  EXPECT_GT(bed.settle_time, 3.0);  // the column's free-fall time
  EXPECT_GT(bed.profile.bulk_packing_fraction, 0.5);
}

TEST(Pour, PlacementHasNoOverlapsAndSparesTheIntruder) {
  PourSpec s;
  s.lx = s.ly = 8;
  s.grains = 600;
  s.intruder_diameter = 3;
  s.intruder_x = 0.5;  // straddles the periodic boundary
  s.intruder_y = 4;
  double top = 0;
  const Particles p = place_grains(s, 5.0, &top);
  ASSERT_EQ(p.size(), 600u);
  const Box box{8, 8, true};
  const Vec3 intruder(0.5, 4, 5.0);
  for (std::size_t i = 0; i < p.size(); ++i) {
    EXPECT_GE(p.radius[i], 0.45);
    EXPECT_LE(p.radius[i], 0.55);
    EXPECT_GE(p.x[i].z(), p.radius[i]);
    EXPECT_LE(p.x[i].z(), top);
    EXPECT_GE(box.min_image(p.x[i] - intruder).norm(), 1.5 + p.radius[i]);
    for (std::size_t j = i + 1; j < p.size(); ++j)
      ASSERT_GE(box.min_image(p.x[i] - p.x[j]).norm(), p.radius[i] + p.radius[j]) << i << " " << j;
  }
}

TEST(Pour, RejectsBadInputWithTheKeyName) {
  auto message = [](PourSpec s) {
    try {
      pour(s, false);
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  PourSpec s;
  s.depth = 5;
  PourSpec bad = s;
  bad.lx = -1;
  EXPECT_NE(message(bad).find("'lx'"), std::string::npos);
  bad = s;
  bad.intruder_x = 25;  // box is 20
  EXPECT_NE(message(bad).find("'intruder_x'"), std::string::npos);
  bad = s;
  bad.depth = 500;
  EXPECT_NE(message(bad).find("deeper than the bed"), std::string::npos);
  bad = s;
  bad.intruder_z = 3;  // both depth and intruder_z
  EXPECT_NE(message(bad).find("exactly one"), std::string::npos);
  bad = s;
  bad.contact.mu = -1;
  EXPECT_NE(message(bad).find("'mu'"), std::string::npos);
  bad = s;
  bad.dt = 1.0;
  EXPECT_NE(message(bad).find("dt <="), std::string::npos);
}

// The intruder is placed before the bed exists, from bulk_packing_estimate(mu); the table was
// measured with seed 1, so these beds (seed 7) are out of sample. Before the table a fixed 0.59
// left frictionless beds 1.6 d and mu = 0.5 beds 0.7 d short of the requested depth.
class PourDepth : public ::testing::TestWithParam<double> {};

TEST_P(PourDepth, BedSettlesDenseAtTheRequestedDepth) {
  PourSpec s;
  s.lx = s.ly = 10;
  s.grains = 1500;
  s.intruder_diameter = 2;
  s.intruder_x = s.intruder_y = 5;
  s.depth = 6;
  s.seed = 7;
  s.contact = ContactParams{}.with_stiffness(2e4);
  s.contact.mu = GetParam();
  s.ke_threshold = 1e-5;
  s.max_settle_time = 40;
  const Bed bed = pour(s, false);
  if (s.contact.mu > 0) {
    EXPECT_EQ(bed.stop_reason, "threshold");  // frictionless beds creep
  }
  EXPECT_GT(bed.profile.bulk_packing_fraction, 0.58);
  EXPECT_LT(bed.profile.bulk_packing_fraction, 0.67);
  EXPECT_NEAR(bed.depth, 6.0, 0.4);
  const Particles& p = bed.state.particles;
  EXPECT_GT(p.count(Species::Frozen), 50u);
  for (std::size_t i = 0; i < p.size(); ++i) {
    EXPECT_GT(p.x[i].z(), 0.0);
    if (p.species[i] == Species::Frozen) {
      EXPECT_LT(p.x[i].z(), 0.6);
    }
  }
  EXPECT_EQ(p.species[bed.intruder], Species::Intruder);
  EXPECT_DOUBLE_EQ(p.x[bed.intruder].z() + bed.depth, bed.surface_height);
}

INSTANTIATE_TEST_SUITE_P(Friction, PourDepth, ::testing::Values(0.0, 0.5));

TEST(Pour, PackingEstimateFollowsTheMeasuredTable) {
  EXPECT_DOUBLE_EQ(bulk_packing_estimate(0.0), 0.657);
  EXPECT_DOUBLE_EQ(bulk_packing_estimate(0.9), 0.598);
  EXPECT_DOUBLE_EQ(bulk_packing_estimate(5.0), 0.598);
  EXPECT_NEAR(bulk_packing_estimate(0.4), 0.5 * (0.619 + 0.604), 1e-12);
  PourSpec a, b;
  a.grains = b.grains = 4000;
  a.depth = b.depth = 5;
  a.contact.mu = 0;
  b.contact.mu = 0.9;
  // A denser (frictionless) bed is lower, so its intruder sits lower for the same depth.
  EXPECT_LT(intruder_height_for_depth(a), intruder_height_for_depth(b));
  b.packing_estimate = 0.657;  // an explicit estimate wins over the table
  EXPECT_DOUBLE_EQ(intruder_height_for_depth(a), intruder_height_for_depth(b));
}

namespace {
PourSpec small_pour() {
  PourSpec s;
  s.lx = s.ly = 8;
  s.intruder_x = s.intruder_y = 4;
  s.grains = 500;
  s.depth = 3;
  s.contact = ContactParams{}.with_stiffness(2e4);
  s.ke_threshold = 1e-9;  // runs to max_settle_time
  s.max_settle_time = 6;
  return s;
}
}  // namespace

TEST(Pour, ResumedFromACheckpointItEndsBitwiseAsAnUninterruptedPour) {
  PourSpec s = small_pour();
  s.checkpoint_every = 2;  // every second check: t = 1, 2, ...
  std::vector<std::pair<Simulation::State, PourRecord>> saved;
  Pour first(s);
  first.run(false, [&](const Pour& p) { saved.emplace_back(p.state(), p.record()); });
  const Bed& whole = first.result();
  ASSERT_GE(saved.size(), 5u);
  for (std::size_t k : {std::size_t{0}, std::size_t{3}}) {
    Pour resumed(s, saved[k].first, saved[k].second);
    resumed.run(false, [](const Pour&) {});
    const Bed& again = resumed.result();
    const Particles& a = whole.state.particles;
    const Particles& b = again.state.particles;
    ASSERT_EQ(a.size(), b.size());
    for (std::size_t i = 0; i < a.size(); ++i) {
      ASSERT_EQ(a.x[i], b.x[i]) << k << " " << i;
      ASSERT_EQ(a.v[i], b.v[i]) << k << " " << i;
      ASSERT_EQ(a.omega[i], b.omega[i]) << k << " " << i;
      ASSERT_EQ(a.species[i], b.species[i]) << k << " " << i;
    }
    EXPECT_EQ(whole.surface_height, again.surface_height);
    EXPECT_EQ(whole.settle_time, again.settle_time);
  }
}

TEST(Pour, AnOverlapOverTheBoundStopsThePour) {
  // Grains falling ~5 d onto the wall at kn = 2e4 overlap it by ~0.05 d: over a 0.02 d bound.
  PourSpec s = small_pour();
  s.max_overlap = 0.02;
  try {
    pour(s, false);
    FAIL() << "the pour ran past an overlap over its bound";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("exceeds max_overlap = 0.02 d"), std::string::npos) << e.what();
  }
  s.max_overlap = 0.1;
  EXPECT_NO_THROW(pour(s, false));
}

TEST(Pour, SanityReportReadsAsThePulls) {
  // A pour's intruder is held fixed: no work term, and what the grains lost was dissipated.
  SanityFigures f;
  f.grains = 500;
  f.largest_overlap = 0.05;
  f.energy_start = 100;
  f.energy_end = 40;
  f.particle_steps_per_second = 2e6;
  EXPECT_EQ(sanity_line(f),
            "sanity: grains lost 0 of 500; largest overlap 0.05 d; energy of the grains 100 -> 40, "
            "dissipated 60 (rho g d^4); 2e+06 particle-steps/s\n");
  f.work = 30;
  EXPECT_NE(sanity_line(f).find("100 -> 40, work by the intruder 30, dissipated 90 (rho g d^4)"),
            std::string::npos);
}

namespace {
double median_speed(const Particles& p) {
  std::vector<double> speeds;
  for (std::size_t i = 0; i < p.size(); ++i)
    if (p.species[i] == Species::Mobile) speeds.push_back(p.v[i].norm());
  std::nth_element(speeds.begin(), speeds.begin() + speeds.size() / 2, speeds.end());
  return speeds[speeds.size() / 2];
}
}  // namespace

TEST(Pour, SettleDampingKeepsThePackingAndResumesBitwise) {
  // The same pour with and without the viscous drag once the column has fallen (t = 5.2 here):
  // packed the same within what two seeds differ by (0.01, BedSettlesDenseAtTheRequestedDepth),
  // the surface within 0.2 d, and moving less. (What it drains, measured on beds of 1,500 and
  // 70,000 grains, is in docs/pour-and-pull.md; the drag itself is tested in
  // ViscousDampingDecaysAFreeGrains...)
  PourSpec s = small_pour();
  s.max_settle_time = 12;
  const Bed plain = pour(s, false);
  s.settle_damping = 1;
  s.checkpoint_every = 16;  // t = 8
  std::vector<std::pair<Simulation::State, PourRecord>> saved;
  Pour damped(s);
  damped.run(false, [&](const Pour& p) { saved.emplace_back(p.state(), p.record()); });
  const Bed& bed = damped.result();
  EXPECT_LT(median_speed(bed.state.particles), median_speed(plain.state.particles));
  EXPECT_NEAR(bed.profile.bulk_packing_fraction, plain.profile.bulk_packing_fraction, 0.01);
  EXPECT_NEAR(bed.surface_height, plain.surface_height, 0.2);
  // Resumed from a checkpoint taken while the drag acts, it ends bitwise the same.
  ASSERT_FALSE(saved.empty());
  ASSERT_NEAR(static_cast<double>(saved[0].first.steps) * bed.dt, 8, 0.1);
  Pour resumed(s, saved[0].first, saved[0].second);
  resumed.run(false, [](const Pour&) {});
  EXPECT_EQ(resumed.result().state.particles.x, bed.state.particles.x);
  EXPECT_EQ(resumed.result().state.particles.v, bed.state.particles.v);
}
