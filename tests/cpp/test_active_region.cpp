// The active region (engine/active_region.hpp): when grains fall asleep and wake, that a region
// wider than the box changes nothing (bitwise), and that a pull with sleeping grains resumes
// from a checkpoint bitwise. The fast path against the oracle with sleeping grains is in
// test_oracle.cpp.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "core/error.hpp"
#include "helpers.hpp"
#include "protocol/pull.hpp"

using namespace granudrag;
using support::small_bed;

namespace {

// An intruder at the origin moving along +x at 1, a grain at x = 10 and one at x = 2.5.
struct Pair {
  Particles p;
  Box box{40, 40, false};
  int intruder, far, near;
  Pair() {
    far = static_cast<int>(p.add(Vec3(10, 0, 0), 0.5, Species::Mobile));
    near = static_cast<int>(p.add(Vec3(2.5, 0, 0), 0.5, Species::Mobile));
    intruder = static_cast<int>(p.add(Vec3(0, 0, 0), 1.0, Species::Intruder));
    p.v[intruder] = Vec3(1, 0, 0);
  }
};

ActiveRegionSettings settings() {
  ActiveRegionSettings s;
  s.radius = 4;
  s.sleep_distance = 0.01;
  s.sleep_time = 0.3;
  s.wake_force = 0.5;
  s.check_interval = 0.1;  // 10 steps of dt = 0.01: dwell 3 checks
  return s;
}

// Runs `steps` steps of bookkeeping, the held grains' force being `force` at every step.
bool run(ActiveRegion& region, Pair& s, long& step, long steps, const Vec3& force = Vec3(0, 0, 0)) {
  bool changed = false;
  for (long k = 0; k < steps; ++k) {
    ++step;
    for (int i : {s.far, s.near})
      if (region.held()[i]) region.add_force(i, force);
    changed |= region.after_step(s.p, s.box, step, Vec3(0, 0, -1));
  }
  return changed;
}

// A pull through the small bed in which most grains fall asleep early: outside 3 d of the
// intruder, at rest after 0.2 time units (0.05 d over sleep_time at V = 0.5).
PullSpec sleeping_pull() {
  PullSpec spec;
  spec.speed = 0.5;
  spec.distance = 1.0;
  spec.active.radius = 3;
  spec.active.sleep_time = 0.2;
  spec.sleep_speed = 0.5;
  spec.sleep_speed_max = 1.0;  // a rest test loose enough for a small bed still settling
  return spec;
}

}  // namespace

TEST(ActiveRegion, AGrainAtRestFarFromTheIntruderFallsAsleepAfterTheDwellAndIsHeldStill) {
  Pair s;
  ActiveRegion region(settings(), 0.01, s.p);
  EXPECT_EQ(region.check_steps(), 10);
  long step = 0;
  s.p.v[s.far] = Vec3(0.2, 0, 0);  // fast, yet it does not go anywhere: speed is not the test
  EXPECT_FALSE(run(region, s, step, 29));
  EXPECT_FALSE(region.held()[s.far]);  // two checks at rest: not yet
  EXPECT_TRUE(run(region, s, step, 1));
  EXPECT_TRUE(region.held()[s.far]);  // the third: asleep, and held still
  EXPECT_EQ(s.p.v[s.far], Vec3(0, 0, 0));
  EXPECT_FALSE(region.held()[s.near]);  // inside the radius: never
  EXPECT_EQ(region.sleeping(), 1);
}

TEST(ActiveRegion, AGrainThatDriftsFartherThanTheSleepDistanceStaysAwake) {
  Pair s;
  ActiveRegion region(settings(), 0.01, s.p);
  long step = 0;
  for (int check = 0; check < 6; ++check) {
    s.p.x[s.far].x() += 0.004;  // 0.012 d over any three checks: above sleep_distance
    run(region, s, step, 10);
    EXPECT_FALSE(region.held()[s.far]) << "check " << check;
  }
}

TEST(ActiveRegion, ASleepingGrainWakesWhenItsLoadChangesByTheWakeForceOrTheIntruderComesNear) {
  Pair s;
  const double weight = s.p.mass[s.far];  // g = 1
  ActiveRegion region(settings(), 0.01, s.p);
  long step = 0;
  run(region, s, step, 30);
  ASSERT_TRUE(region.held()[s.far]);
  const Vec3 load(0, 0, -3.0);  // the interval after it fell asleep sets the reference
  run(region, s, step, 10, load);
  run(region, s, step, 30, load + Vec3(0.45 * weight, 0, 0));  // below wake_force = 0.5
  EXPECT_TRUE(region.held()[s.far]);
  EXPECT_TRUE(run(region, s, step, 10, load + Vec3(0.55 * weight, 0, 0)));
  EXPECT_FALSE(region.held()[s.far]);
  EXPECT_EQ(region.wake_ups(), 1);

  run(region, s, step, 30);           // asleep again, then the intruder comes: within the radius plus
  ASSERT_TRUE(region.held()[s.far]);  // the travel to the next check (4 + 0.1 d)
  s.p.x[s.intruder].x() = 10 - 4.05;
  run(region, s, step, 10);
  EXPECT_FALSE(region.held()[s.far]);
  EXPECT_EQ(region.wake_ups(), 2);
}

// wake_load: the threshold is the larger of wake_force m g and wake_load times the grain's mean
// contact force with its held partners (which the simulation hands over with the held forces).
TEST(ActiveRegion, WithWakeLoadAHeavilyLoadedGrainWakesAtThatFractionOfItsContactForce) {
  for (const double contact : {20.0, 1.0}) {  // mean contact force, in weights
    Pair s;
    const double weight = s.p.mass[s.far];  // g = 1
    ActiveRegionSettings set = settings();
    set.wake_load = 0.1;  // 2 weights at 20, 0.1 (below wake_force's 0.5) at 1
    ActiveRegion region(set, 0.01, s.p);
    ASSERT_NE(region.held_loads(), nullptr);
    long step = 0;
    run(region, s, step, 30);
    ASSERT_TRUE(region.held()[s.far]);
    (*region.held_loads())[s.far] = contact * weight;
    const Vec3 load(0, 0, -3.0);
    run(region, s, step, 10, load);
    const double threshold = std::max(0.5, 0.1 * contact);  // weights
    run(region, s, step, 30, load + Vec3(0.9 * threshold * weight, 0, 0));
    EXPECT_TRUE(region.held()[s.far]) << contact;
    run(region, s, step, 10, load + Vec3(1.1 * threshold * weight, 0, 0));
    EXPECT_FALSE(region.held()[s.far]) << contact;
  }
  ActiveRegion off(settings(), 0.01, Pair().p);
  EXPECT_EQ(off.held_loads(), nullptr);  // 0: no loads asked for, none kept
  ActiveRegionSettings negative = settings();
  negative.wake_load = -0.1;
  EXPECT_THROW(ActiveRegion(negative, 0.01, Pair().p), Error);
}

TEST(ActiveRegion, ARegionWiderThanTheBoxChangesNoBitOfAPull) {
  support::ThreadCount tc(1);  // the 2-thread schedules with sleeping grains: test_oracle.cpp
  PullSpec spec;
  spec.speed = 0.5;
  spec.distance = 0.5;
  Pull plain(small_bed(), spec);
  plain.run(false);
  spec.active.radius = 100;
  Pull wide(small_bed(), spec);
  wide.run(false);
  ASSERT_NE(wide.simulation().active_region(), nullptr);
  EXPECT_EQ(wide.simulation().active_region()->sleeping(), 0);
  EXPECT_EQ(plain.record().fx, wide.record().fx);
  EXPECT_EQ(plain.record().contacts, wide.record().contacts);
  EXPECT_EQ(plain.simulation().particles().x, wide.simulation().particles().x);
  EXPECT_EQ(plain.simulation().particles().omega, wide.simulation().particles().omega);
}

TEST(ActiveRegion, APullWithSleepingGrainsResumesFromACheckpointBitwise) {
  support::ThreadCount tc(1);  // the 2-thread schedules with sleeping grains: test_oracle.cpp
  for (const double wake_load : {0.0, 0.3}) {
    SCOPED_TRACE(wake_load);
    PullSpec spec = sleeping_pull();
    spec.active.wake_load = wake_load;
    spec.checkpoint_every = 400;
    Pull whole(small_bed(), spec);
    const support::Checkpoints checkpoints = support::run_keeping_checkpoints(whole);
    ASSERT_GE(checkpoints.size(), 3u);
    const Simulation::State& at = checkpoints[2].first;
    const long asleep = std::count(at.region.held.begin(), at.region.held.end(), 1) -
                        static_cast<long>(small_bed().state.particles.count(Species::Frozen));
    ASSERT_GT(asleep, 100) << "the checkpoint should catch grains asleep";
    ASSERT_GT(std::count(at.region.quiet.begin(), at.region.quiet.end(), ActiveRegion::kQuiet), 50)
        << "and some of them quiet";
    Pull resumed(small_bed(), spec, at, checkpoints[2].second);
    resumed.run(false, [](const Pull&) {});
    ASSERT_TRUE(support::same_motion(whole.simulation().particles(), resumed.simulation().particles()));
    EXPECT_EQ(whole.record().fx, resumed.record().fx);
    EXPECT_EQ(whole.record().sleeping, resumed.record().sleeping);
    EXPECT_EQ(whole.simulation().active_region()->wake_ups(),
              resumed.simulation().active_region()->wake_ups());
    EXPECT_EQ(at.region.held_load.size(), wake_load > 0 ? whole.simulation().particles().size() : 0u);
  }
}

// Quiet grains (held, no awake partner) are skipped by the integrator; stepping them instead
// must give the same bits, wake-ups and all, with the default wake test.
TEST(ActiveRegion, SkippingQuietGrainsChangesNoBitOfAPull) {
  support::ThreadCount tc(1);
  PullSpec spec = sleeping_pull();
  spec.checkpoint_every = 200;  // to look at the quiet grains on the way
  long most_quiet = 0;
  Pull skipping(small_bed(), spec);
  skipping.run(false, [&](const Pull& p) {
    const auto& quiet = p.simulation().active_region()->quiet();
    most_quiet =
        std::max(most_quiet, static_cast<long>(std::count(quiet.begin(), quiet.end(), ActiveRegion::kQuiet)));
  });
  spec.active.skip_quiet = false;
  Pull stepping(small_bed(), spec);
  stepping.run(false, [](const Pull&) {});
  const ActiveRegion& region = *skipping.simulation().active_region();
  EXPECT_GT(most_quiet, 50);
  EXPECT_GT(region.wake_ups(), 0);
  EXPECT_EQ(region.wake_ups(), stepping.simulation().active_region()->wake_ups());
  EXPECT_EQ(skipping.record().fx, stepping.record().fx);
  EXPECT_EQ(skipping.record().sleeping, stepping.record().sleeping);
  EXPECT_EQ(skipping.simulation().particles().x, stepping.simulation().particles().x);
  EXPECT_EQ(skipping.simulation().particles().v, stepping.simulation().particles().v);
}

// A slow pull's failure zone creeps at a few percent of V: the rest test is relative to V, the
// distance a grain may move over sleep_time being sleep_speed times the intruder's travel.
TEST(ActiveRegion, ThePullSetsTheRestDistanceFromItsSpeed) {
  PullSpec spec;
  spec.active.radius = 4;
  for (double speed : {0.5, 0.03}) {
    spec.speed = speed;
    Pull pull(small_bed(), spec);
    EXPECT_DOUBLE_EQ(pull.simulation().active_region()->settings().sleep_distance,
                     spec.sleep_speed * speed * 1.0);
  }
  {
    // A fast pull: the rest test's speed is capped at sleep_speed_max (0.014 d per time unit).
    spec.speed = 5.0;
    Pull pull(small_bed(), spec);
    EXPECT_DOUBLE_EQ(pull.simulation().active_region()->settings().sleep_distance, 0.014 * 1.0);
  }
  spec.active.sleep_time = 0;  // a check every step: the window is one step
  spec.speed = 0.5;
  Pull pull(small_bed(), spec);
  EXPECT_DOUBLE_EQ(pull.simulation().active_region()->settings().sleep_distance,
                   spec.sleep_speed * 0.5 * small_bed().dt);
}

// The force of a given creep grows with the contacts' stiffness, so the wake test's default does:
// the values validated at K_n = 2e4, 2e5 and 2e6, four times more per decade beyond.
TEST(ActiveRegion, TheWakeTestDefaultsToTheValidatedValuesAndGrowsFourfoldPerDecade) {
  EXPECT_EQ(default_wake_force(2e4), 0.5);
  EXPECT_EQ(default_wake_force(2e5), 0.5);
  EXPECT_DOUBLE_EQ(default_wake_force(2e6), 2.0);
  EXPECT_DOUBLE_EQ(default_wake_force(2e7), 8.0);
  EXPECT_NEAR(default_wake_force(2e8), 32.0, 1e-12);
  EXPECT_NEAR(default_wake_force(6.3245553e5), 1.0, 1e-6);  // half a decade: a factor 2
  // A pull leaves it to the bed's K_n unless it is given.
  PullSpec spec;
  spec.active.radius = 4;
  spec.speed = 0.5;
  for (double kn : {2e4, 2e6}) {
    Bed bed = small_bed();
    bed.contact.kn = kn;
    bed.dt /= 10;  // resolves a collision at 2e6
    Pull pull(bed, spec);
    EXPECT_DOUBLE_EQ(pull.simulation().active_region()->settings().wake_force, default_wake_force(kn)) << kn;
  }
  spec.active.wake_force = 1.5;
  Bed bed = small_bed();
  bed.contact.kn = 2e6;
  bed.dt /= 10;
  Pull pull(bed, spec);
  EXPECT_EQ(pull.simulation().active_region()->settings().wake_force, 1.5);
}

TEST(ActiveRegion, ARadiusInsideTheGrainsAroundTheIntruderIsRefused) {
  PullSpec spec;
  spec.active.radius = 2.5;  // D/2 + 2 = 3
  try {
    Pull pull(small_bed(), spec);
    FAIL() << "accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("active_radius"), std::string::npos) << e.what();
  }
}

// The awake grains lie in a few places of the index range (about the intruder, and a failure
// zone): the integrator's split must share the bodies it steps, not all bodies, between threads.
TEST(ActiveRegion, TheIntegratorSplitsTheBodiesItStepsEvenlyBetweenThreads) {
  support::ThreadCount tc(2);
  PullSpec spec = sleeping_pull();
  spec.checkpoint_every = 200;
  long checks = 0, worst_share_permille = 500, species_worst = 500;
  Pull pull(small_bed(), spec);
  pull.run(false, [&](const Pull& run) {
    const Simulation& sim = run.simulation();
    const Particles& p = sim.particles();
    const ActiveRegion& region = *sim.active_region();
    // The integrator's cost of a body: an awake grain 4, a held one stepped 2, a quiet one 0.
    auto cost = [&](long i) {
      if (region.quiet()[i] == ActiveRegion::kQuiet) return 0L;
      if (p.species[i] != Species::Mobile) return 1L;
      return region.held()[i] ? 2L : 4L;
    };
    long total = 0, first = 0, quiet = 0;
    for (long i = 0; i < static_cast<long>(p.size()); ++i) total += cost(i), quiet += cost(i) == 0;
    if (quiet < 50) return;  // nothing much asleep yet
    ++checks;
    const auto [b0, e0] = sim.body_range(0, 2);
    for (long i = b0; i < e0; ++i) first += cost(i);
    const long share = 1000 * first / total;
    worst_share_permille = std::max(worst_share_permille, std::max(share, 1000 - share));
    // What a split of every body by species would have given thread 0: its first half.
    long by_species = 0;
    for (long i = 0; i < static_cast<long>(p.size()) / 2; ++i) by_species += cost(i);
    const long s = 1000 * by_species / total;
    species_worst = std::max(species_worst, std::max(s, 1000 - s));
  });
  ASSERT_GT(checks, 0);
  // Each thread within 10 % of half, where an index split would be off by more (the test is
  // not vacuous).
  EXPECT_LE(worst_share_permille, 550);
  EXPECT_GT(species_worst, 600);
}
