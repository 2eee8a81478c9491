// The fast path (cells, Verlet lists, transposed gather, threads) against the brute-force
// oracle, on a polydisperse packing with frozen base grains and a large intruder that straddles
// the periodic boundary; reproducibility per thread count; history surviving rebuilds.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>
#include <utility>
#include <vector>

#include "contact/contact_history.hpp"
#include "contact/neighbor_list.hpp"
#include "contact/verlet_contacts.hpp"
#include "core/ordered_sum.hpp"
#include "core/spatial_order.hpp"
#include "helpers.hpp"

using namespace granudrag;
using granudrag::support::ThreadCount;

namespace {

// ~700 grains, the lowest frozen, an intruder of D = 4 centred 0.3 d from the x boundary,
// moving along +x at 1 sqrt(gd), grains agitated so that many contacts carry history.
struct Scene {
  Particles particles;
  Box box;
};

// shuffled: the grains in random order, so that a row's partners are anywhere in index (as in
// a bed imported from elsewhere), which rules out the two-colour schedule.
Scene intruder_scene(bool shuffled = false) {
  LatticeBed bed = fcc_bed(800, 5);
  randomize_velocities(bed.particles, 1.0, 2.0, 6);
  const Vec3 centre(0.3, 0.5 * bed.box.ly, 3.0);
  const double R = 2.0;
  Particles p;
  for (std::size_t i = 0; i < bed.particles.size(); ++i) {
    const Vec3 x = bed.particles.x[i];
    if (bed.box.min_image(x - centre).norm() < R + bed.particles.radius[i] + 0.005) continue;
    const std::size_t k = p.add(x, bed.particles.radius[i], Species::Mobile);
    p.v[k] = bed.particles.v[i];
    p.omega[k] = bed.particles.omega[i];
  }
  if (shuffled) {
    std::vector<std::size_t> order(p.size());
    std::iota(order.begin(), order.end(), 0);
    std::shuffle(order.begin(), order.end(), std::mt19937_64(9));
    Particles q;
    for (std::size_t i : order) {
      const std::size_t k = q.add(p.x[i], p.radius[i], Species::Mobile);
      q.v[k] = p.v[i];
      q.omega[k] = p.omega[i];
    }
    p = q;
  }
  p.freeze_below(0.7);
  const std::size_t in = p.add(centre, R, Species::Intruder);
  p.v[in] = Vec3(2.0, 0, 0);
  return {p, bed.box};
}

double force_scale(const Particles& p) {
  double s = 0;
  for (const auto& f : p.f) s = std::max(s, f.norm());
  return s;
}

// What the brute-force oracle computes at each step of a scene: forces, torques and the
// intruder's contacts. On one thread it is serial and deterministic, so it is computed once per
// scene and every fast schedule is compared with the same record (the O(N^2) pass was two
// thirds of the test's time when it ran beside each schedule, 50 s under AddressSanitizer).
struct OracleStep {
  std::vector<Vec3> f, torque;
  int intruder_contacts = 0;
  std::vector<int> intruder_touching;  // sorted: the grains touching the intruder
  double scale = 0;
};

std::vector<int> touching_of(const ContactLoop& contacts, int body) {
  std::vector<int> grains;
  contacts.touching_contacts_of(body, grains);
  std::sort(grains.begin(), grains.end());
  return grains;
}

std::vector<OracleStep> oracle_run(const Scene& scene, const ContactParams& c, int steps) {
  ThreadCount one(1);
  Settings s;
  s.brute_force = true;
  Simulation brute(scene.particles, scene.box, c, s);
  std::vector<OracleStep> record(steps);
  const int intruder = static_cast<int>(scene.particles.size()) - 1;
  for (auto& r : record) {
    brute.step();
    r.f = brute.particles().f;
    r.torque = brute.particles().torque;
    r.intruder_contacts = brute.contacts().contacts_of(intruder);
    r.intruder_touching = touching_of(brute.contacts(), intruder);
    r.scale = force_scale(brute.particles());
  }
  return record;
}

}  // namespace

TEST(Oracle, FastForcesEqualBruteForceOnIntruderScene) {
  constexpr int kSteps = 600;
  const ContactParams c = support::soft_params(0.5);
  const Scene scenes[2] = {intruder_scene(false), intruder_scene(true)};
  const std::vector<OracleStep> oracle[2] = {oracle_run(scenes[0], c, kSteps),
                                             oracle_run(scenes[1], c, kSteps)};
  for (const auto& [threads, shuffled] : {std::pair{1, false}, {2, false}, {2, true}, {8, false}}) {
    ThreadCount tc(threads);
    const Scene& scene = scenes[shuffled];
    ASSERT_GT(scene.particles.count(Species::Frozen), 20u);
    Settings fast_s;
    fast_s.skin = 0.05;  // thin: several rebuilds within the test
    Simulation fast(scene.particles, scene.box, c, fast_s);
    int intruder_contacts = 0, most_intruder_contacts = 0;
    for (int step = 0; step < kSteps; ++step) {
      fast.step();
      const Particles& a = fast.particles();
      const OracleStep& b = oracle[shuffled][step];
      for (std::size_t i = 0; i < a.size(); ++i) {
        ASSERT_LT(support::rel_diff(a.f[i], b.f[i], b.scale), 1e-9)
            << "force on " << i << " at step " << step << ", threads " << threads;
        ASSERT_LT(support::rel_diff(a.torque[i], b.torque[i], b.scale), 1e-9)
            << "torque on " << i << " at step " << step << ", threads " << threads;
      }
      const int intruder = static_cast<int>(a.size()) - 1;
      intruder_contacts = fast.contacts().contacts_of(intruder);
      most_intruder_contacts = std::max(most_intruder_contacts, intruder_contacts);
      ASSERT_EQ(intruder_contacts, b.intruder_contacts) << "step " << step;
      // The contacts present (the time-weighted contact angle): the same grains, each touching.
      const std::vector<int> touching = touching_of(fast.contacts(), intruder);
      ASSERT_EQ(touching, b.intruder_touching) << "step " << step;
      ASSERT_EQ(static_cast<int>(touching.size()), intruder_contacts) << "step " << step;
      for (int g : touching)
        ASSERT_LT(scene.box.min_image(a.x[g] - a.x[intruder]).norm(), a.radius[g] + a.radius[intruder])
            << "grain " << g << " at step " << step;
    }
    EXPECT_GE(most_intruder_contacts, 3);  // the intruder really was in the thick of it
    const auto& fc = dynamic_cast<const VerletContacts&>(fast.contacts());
    EXPECT_GT(fc.list().builds(), 1);  // and the lists were rebuilt on the way
    // Both threaded schedules were checked: two colours on the ordered lattice, private force
    // arrays on the shuffled one and on the ordered one at 8 threads, whose blocks are too
    // thin for the colours.
    EXPECT_EQ(fc.colored(), threads == 2 && !shuffled) << "threads " << threads;
    // Private arrays are cleared and summed over what each thread's rows reach, not from its
    // first row to the end (which on the ordered scene at 8 threads would be about 3.5 N).
    if (threads == 8) {
      EXPECT_LT(fc.private_span(), 2 * static_cast<long>(scene.particles.size()));
    }
  }
}

TEST(Oracle, WithSleepingGrainsTheFastPathComputesWhatTheOracleDoes) {
  // The active region: grains outside 3.5 d of the intruder fall asleep after 150 steps of
  // collisions (checks every step here; a sleep distance and a wake force so large that only
  // the intruder's approach wakes them), and the intruder moving on wakes those it nears. Both
  // paths skip the pairs of two held bodies and compute every other, and the checks of every
  // sample interval (contact counts, largest overlap, elastic energy) agree.
  // One thread in spatial order, two on the shuffled scene (private force arrays); the
  // two-colour schedule with held grains is checked bitwise in AnActiveRegionWider... and by the
  // pulls of test_active_region.cpp.
  for (const auto& [threads, shuffled] : {std::pair{1, false}, {2, true}}) {
    ThreadCount tc(threads);
    const Scene scene = intruder_scene(shuffled);
    Settings fast_s;
    fast_s.skin = 0.05;
    fast_s.active.radius = 3.5;
    fast_s.active.sleep_distance = 10;
    const ContactParams c = support::soft_params(0.5);
    const double dt = Simulation(scene.particles, scene.box, c, Settings{}).dt();
    fast_s.active.sleep_time = 150 * dt;
    fast_s.active.wake_force = 1e9;
    fast_s.active.wake_load = 1e-9;     // the held loads computed on both paths, the test unchanged
    fast_s.active.check_interval = dt;  // every step
    Settings brute_s = fast_s;
    brute_s.brute_force = true;
    Simulation fast(scene.particles, scene.box, c, fast_s);
    Simulation brute(scene.particles, scene.box, c, brute_s);
    const std::size_t n = scene.particles.size();
    std::vector<std::uint8_t> always_held(n, 1);  // held at every step since step 250
    std::vector<PairHistory> springs_then;
    Particles then;
    long held_drifts = 0;  // held grains found away from their build position, over the steps
    for (int step = 0; step < 450; ++step) {
      fast.step();
      brute.step();
      const Particles& a = fast.particles();
      const Particles& b = brute.particles();
      ASSERT_EQ(fast.active_region()->held(), brute.active_region()->held()) << "step " << step;
      // The integrator does not measure a held grain's drift since the last list build: it has
      // not moved since it was last measured awake, within the limit, or since a build zeroed
      // it, so it cannot call for a rebuild.
      const std::vector<Vec3>& built = *fast.contacts().build_positions();
      for (std::size_t i = 0; i < n; ++i) {
        if (!fast.active_region()->held()[i] || a.species[i] != Species::Mobile) continue;
        const double drift_sq = scene.box.min_image(a.x[i] - built[i]).squaredNorm();
        ASSERT_LE(drift_sq, 0.25 * fast_s.skin * fast_s.skin) << "held grain " << i << " at step " << step;
        held_drifts += drift_sq > 0;
      }
      const double scale = force_scale(b);
      for (std::size_t i = 0; i < n; ++i) {
        ASSERT_LT(support::rel_diff(a.f[i], b.f[i], scale), 1e-9)
            << "force on " << i << " at step " << step << ", threads " << threads;
        ASSERT_LT(support::rel_diff(a.torque[i], b.torque[i], scale), 1e-9)
            << "torque on " << i << " at step " << step << ", threads " << threads;
      }
      if (step % 10 == 0) {
        // The checks of every sample interval: the fast path takes the held pairs' part from
        // what it kept since the held set or the lists last changed, the oracle scans them all.
        std::vector<int> counts_a(n, 0), counts_b(n, 0);
        fast.contacts().count_contacts(counts_a);
        brute.contacts().count_contacts(counts_b);
        ASSERT_EQ(counts_a, counts_b) << "step " << step << ", threads " << threads;
        ASSERT_EQ(fast.contacts().max_overlap(a, scene.box), brute.contacts().max_overlap(b, scene.box))
            << "step " << step;
        const double e_brute = brute.contacts().elastic_energy(b, scene.box, c);
        ASSERT_NEAR(fast.contacts().elastic_energy(a, scene.box, c), e_brute, 1e-9 * e_brute)
            << "step " << step;
      }
      if (step == 250) {
        springs_then = fast.state().pair_history;
        then = a;
      }
      if (step >= 250)
        for (std::size_t i = 0; i < n; ++i) always_held[i] &= fast.active_region()->held()[i];
    }
    const ActiveRegion& region = *fast.active_region();
    EXPECT_GT(region.sleeping(), 300) << "most of the scene asleep";
    EXPECT_GT(held_drifts, 20) << "grains that fell asleep after moving since a build";
    // Most of them quiet, skipped by the fast path's integrator and stepped by the oracle's.
    EXPECT_GT(std::count(region.quiet().begin(), region.quiet().end(), ActiveRegion::kQuiet), 200);
    EXPECT_EQ(std::count(brute.active_region()->quiet().begin(), brute.active_region()->quiet().end(), 0),
              static_cast<long>(n));
    EXPECT_GT(region.wake_ups(), 0) << "the intruder woke some";
    EXPECT_EQ(region.wake_ups(), brute.active_region()->wake_ups());
    // The held partners' mean contact force, by the lists and by every pair.
    const std::vector<double>& load_a = region.state().held_load;
    const std::vector<double>& load_b = brute.active_region()->state().held_load;
    ASSERT_EQ(load_a.size(), n);
    ASSERT_EQ(load_b.size(), n);
    long loaded = 0;
    for (std::size_t i = 0; i < n; ++i) {
      ASSERT_NEAR(load_a[i], load_b[i], 1e-9 * (1 + load_b[i])) << i;
      loaded += load_b[i] > 0;
    }
    EXPECT_GT(loaded, 20) << "held grains with held partners in touch";
    // What was held throughout has not moved, nor have the springs between two such bodies.
    long unchanged = 0;
    for (std::size_t i = 0; i < n; ++i) {
      if (always_held[i] && scene.particles.species[i] == Species::Mobile) {
        ASSERT_EQ(scene.box.min_image(fast.particles().x[i] - then.x[i]).norm(), 0.0) << i;
      }
    }
    const std::vector<PairHistory> springs_now = fast.state().pair_history;
    for (const PairHistory& h : springs_then) {
      if (!always_held[h.i] || !always_held[h.j]) continue;
      const auto it = std::find_if(springs_now.begin(), springs_now.end(),
                                   [&](const PairHistory& k) { return k.i == h.i && k.j == h.j; });
      ASSERT_NE(it, springs_now.end()) << "the spring of " << h.i << "-" << h.j << " was lost";
      ASSERT_EQ(it->shear, h.shear);
      unchanged += h.shear.norm() > 0;
    }
    EXPECT_GT(unchanged, 20) << "springs with history between sleeping grains were kept";
  }
}

TEST(Oracle, AnActiveRegionWiderThanTheBoxChangesNoBitOnEitherThreadSchedule) {
  // Two colours (ordered grains) and private force arrays (shuffled), on 2 threads: frozen rows
  // take the held-partner scan, every other row the plain one, and nothing may differ.
  ThreadCount tc(2);
  for (bool shuffled : {false, true}) {
    const Scene scene = intruder_scene(shuffled);
    const ContactParams c = support::soft_params(0.5);
    Settings wide;
    wide.active.radius = 100;
    wide.active.wake_force = 0.5;
    Simulation plain(scene.particles, scene.box, c, Settings{}), region(scene.particles, scene.box, c, wide);
    plain.run(400);
    region.run(400);
    EXPECT_EQ(region.active_region()->sleeping(), 0);
    EXPECT_EQ(plain.particles().x, region.particles().x) << "shuffled " << shuffled;
    EXPECT_EQ(plain.particles().omega, region.particles().omega) << "shuffled " << shuffled;
    EXPECT_EQ(plain.particles().f, region.particles().f) << "shuffled " << shuffled;
  }
}

TEST(Oracle, GrainsPutInSpatialOrderTakeTheTwoColourScheduleWithTheSameForces) {
  // A bed in random order (as one imported from elsewhere) takes private force arrays; put in
  // spatial order (what import-lammps does), it takes the two colours, and every body feels
  // the same force as before, found through the permutation.
  ThreadCount tc(2);
  const Scene scene = intruder_scene(true);
  const ContactParams c = support::soft_params(0.5);
  Simulation shuffled(scene.particles, scene.box, c, Settings{});
  shuffled.setup();
  const std::vector<std::size_t> order = spatial_order(scene.particles, scene.box);
  const Particles sorted_particles = reordered(scene.particles, order);
  ASSERT_EQ(sorted_particles.species.back(), Species::Intruder);  // intruders stay last
  Simulation sorted(sorted_particles, scene.box, c, Settings{});
  sorted.setup();
  EXPECT_FALSE(dynamic_cast<const VerletContacts&>(shuffled.contacts()).colored());
  EXPECT_TRUE(dynamic_cast<const VerletContacts&>(sorted.contacts()).colored());
  const double scale = force_scale(shuffled.particles());
  for (std::size_t k = 0; k < order.size(); ++k)
    ASSERT_LT(support::rel_diff(sorted.particles().f[k], shuffled.particles().f[order[k]], scale), 1e-12)
        << k;
}

TEST(Oracle, BitwiseReproducibleForAThreadCountAndAgreeingAcrossCounts) {
  // Both threaded schedules: two colours (ordered grains) and private force arrays (shuffled).
  for (bool shuffled : {false, true}) {
    const Scene scene = intruder_scene(shuffled);
    const ContactParams c = support::soft_params(0.5);
    auto run = [&](int threads) {
      support::ThreadCount tc(threads);
      Simulation sim(scene.particles, scene.box, c, Settings{});
      sim.run(500);
      return sim.particles();
    };
    const Particles two_a = run(2), two_b = run(2), one = run(1);
    double worst = 0;
    for (std::size_t i = 0; i < one.size(); ++i) {
      ASSERT_EQ(two_a.x[i], two_b.x[i]) << "particle " << i;  // no race, fixed summation order
      ASSERT_EQ(two_a.omega[i], two_b.omega[i]) << "particle " << i;
      ASSERT_EQ(two_a.f[i], two_b.f[i]) << "particle " << i;
      worst = std::max(worst, scene.box.min_image(one.x[i] - two_a.x[i]).norm());
    }
    EXPECT_LT(worst, 1e-9) << "shuffled " << shuffled;  // counts differ only in summation order
  }
}

TEST(Oracle, ListsAreRebuiltExactlyWhenABodyHasMovedHalfTheSkin) {
  // The integrator measures the displacements in its drift (Simulation::initial_integrate);
  // checked here against a separate measurement, on 2 threads (each thread measures its range).
  ThreadCount tc(2);
  const Scene scene = intruder_scene();
  Settings s;
  s.skin = 0.05;
  Simulation sim(scene.particles, scene.box, support::soft_params(0.5), s);
  sim.setup();
  const auto& lists = dynamic_cast<const VerletContacts&>(sim.contacts()).list();
  int rebuilds = 0;
  for (int step = 0; step < 400; ++step) {
    const std::vector<Vec3> reference = lists.build_positions();
    const long builds = lists.builds();
    sim.step();
    double moved = 0;  // the largest displacement from the last build's positions
    for (std::size_t i = 0; i < reference.size(); ++i)
      moved = std::max(moved, scene.box.min_image(sim.particles().x[i] - reference[i]).norm());
    const bool rebuilt = lists.builds() > builds;
    ASSERT_EQ(rebuilt, moved > 0.5 * s.skin) << "step " << step << ": moved " << moved;
    rebuilds += rebuilt;
  }
  EXPECT_GT(rebuilds, 3);
}

TEST(Oracle, CoordinationAndGuardChecksEqualBruteForceOnTwoThreads) {
  // The passes the run guard and the observables make every sample interval, parallel in the
  // fast path: contact counts (private arrays past thread 0), largest overlap, elastic energy.
  ThreadCount tc(2);
  const Scene scene = intruder_scene();
  Settings fast_s, brute_s;
  brute_s.brute_force = true;
  const ContactParams c = support::soft_params(0.5);
  Simulation fast(scene.particles, scene.box, c, fast_s);
  Simulation brute(scene.particles, scene.box, c, brute_s);
  long counted = 0;
  for (int step = 0; step < 300; ++step) {
    fast.step();
    brute.step();
    std::vector<int> a(scene.particles.size(), 0), b(scene.particles.size(), 0);
    fast.contacts().count_contacts(a);
    brute.contacts().count_contacts(b);
    ASSERT_EQ(a, b) << "step " << step;
    counted += std::accumulate(a.begin(), a.end(), 0L);
  }
  EXPECT_GT(counted, 5000);  // contacts were there to count
  const Particles& p = fast.particles();
  EXPECT_NEAR(fast.contacts().max_overlap(p, scene.box),
              brute.contacts().max_overlap(brute.particles(), scene.box), 1e-12);
  const double e_fast = fast.contacts().elastic_energy(p, scene.box, c);
  const double e_brute = brute.contacts().elastic_energy(brute.particles(), scene.box, c);
  EXPECT_GT(e_brute, 0);
  EXPECT_NEAR(e_fast, e_brute, 1e-9 * e_brute);
}

TEST(Oracle, OrderedSumGivesTheSameBitsForAThreadCount) {
  // Terms spanning 16 orders of magnitude, so that the order of addition shows in the result.
  auto term = [](long i) {
    return std::ldexp(1.0 + 1e-3 * static_cast<double>(i % 97), static_cast<int>(i % 53) - 26);
  };
  const long n = 100001;
  double serial = 0, first_half = 0, second_half = 0;
  for (long i = 0; i < n; ++i) serial += term(i);
  for (long i = 0; i < n / 2; ++i) first_half += term(i);
  for (long i = n / 2; i < n; ++i) second_half += term(i);
  ASSERT_NE(serial, first_half + second_half);  // the terms do tell the orders apart
  {
    ThreadCount tc(1);
    EXPECT_EQ(ordered_sum<double>(n, term), serial);
  }
  ThreadCount tc(2);
  // Thread 0 sums the first half, thread 1 the second, added in that order.
  EXPECT_EQ(ordered_sum<double>(n, term), first_half + second_half);
  for (int repeat = 0; repeat < 20; ++repeat)
    ASSERT_EQ(ordered_sum<double>(n, term), first_half + second_half);
}

TEST(Oracle, TrajectoriesAgreeForDifferentSkins) {
  const Scene scene = intruder_scene();
  const ContactParams c = support::soft_params(0.5);
  auto run = [&](double skin, long* builds) {
    Settings s;
    s.skin = skin;
    Simulation sim(scene.particles, scene.box, c, s);
    sim.run(1500);
    *builds = dynamic_cast<const VerletContacts&>(sim.contacts()).list().builds();
    return sim.particles();
  };
  long thin_builds = 0, thick_builds = 0;
  const Particles thin = run(0.05, &thin_builds), thick = run(0.4, &thick_builds);
  EXPECT_GT(thin_builds, 3 * thick_builds);  // the rebuilds happened at different times
  const Box& box = scene.box;
  double worst = 0;
  for (std::size_t i = 0; i < thin.size(); ++i)
    worst = std::max(
        worst, box.min_image(thin.x[i] - thick.x[i]).norm() + (thin.omega[i] - thick.omega[i]).norm() * 1e-3);
  EXPECT_LT(worst, 1e-9);
}

TEST(ContactHistory, SpringsFollowTheirPairsAcrossRebuilds) {
  PairList before, after;
  before.offset = {0, 2, 3, 3};
  before.partner = {1, 2, 2};
  after.offset = {0, 1, 3, 3};  // pair (0,1) gone, (0,2) kept, (1,2) kept, (1,0)... new (1,3)
  after.partner = {2, 2, 3};
  ContactHistory h;
  h.shear = {Vec3(1, 0, 0), Vec3(2, 0, 0), Vec3(3, 0, 0)};
  h.touching = {1, 1, 1};
  h.carry_over(before, after);
  ASSERT_EQ(h.shear.size(), 3u);
  EXPECT_EQ(h.shear[0], Vec3(2, 0, 0));  // (0,2)
  EXPECT_EQ(h.shear[1], Vec3(3, 0, 0));  // (1,2)
  EXPECT_EQ(h.shear[2], Vec3::Zero());   // (1,3) is new
  EXPECT_EQ(h.touching[2], 0);
}

TEST(NeighborList, RefusesBoxTooSmallForTheIntruder) {
  Particles p;
  p.add(Vec3(1, 1, 1), 0.5, Species::Mobile);
  p.add(Vec3(3, 3, 3), 4.0, Species::Intruder);
  NeighborList list(0.2);
  EXPECT_THROW(list.build(p, Box{9, 9, true}), Error);
  EXPECT_NO_THROW(list.build(p, Box{10, 10, true}));
}
