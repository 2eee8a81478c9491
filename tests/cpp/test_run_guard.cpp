// The run guard alone (engine/run_guard.hpp), on a small lattice bed, and the pull speed limits
// (protocol/speed_limit.hpp) against an independent integration of one Hertz impact.
#include <gtest/gtest.h>

#include <cmath>

#include "core/error.hpp"
#include "engine/run_guard.hpp"
#include "helpers.hpp"
#include "protocol/speed_limit.hpp"

using namespace granudrag;
using support::soft_params;

namespace {

Simulation small_sim() {
  LatticeBed bed = fcc_bed(300, 7);
  return Simulation(std::move(bed.particles), bed.box, soft_params(), Settings{});
}

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

}  // namespace

TEST(RunGuard, ASettlingBedIsClean) {
  Simulation sim = small_sim();
  sim.setup();
  RunGuard guard(GuardLimits{}, sim.energy().total());
  for (int k = 0; k < 5; ++k) {
    sim.run(2000);
    EXPECT_EQ(guard.check(sim, 0.0), "");
  }
  EXPECT_GT(guard.max_overlap_seen(), 0.0);  // the grains have landed on each other
  EXPECT_LT(guard.max_overlap_seen(), 0.1);
  EXPECT_EQ(guard.grains_lost(), 0);
}

TEST(RunGuard, NonFiniteNumbersStopFirst) {
  Simulation sim = small_sim();
  sim.setup();
  RunGuard guard(GuardLimits{}, sim.energy().total());
  sim.particles().v[17] = Vec3(0, NAN, 0);
  sim.particles().x[3].z() = -5;  // also lost, but the NaN is named
  const std::string why = guard.check(sim, 0.0);
  EXPECT_TRUE(contains(why, "non-finite")) << why;
  EXPECT_TRUE(contains(why, "particle 17")) << why;
}

TEST(RunGuard, GrainsOutOfTheBoxAreLost) {
  Simulation sim = small_sim();
  sim.setup();
  GuardLimits limits;
  limits.z_max = 40;
  RunGuard guard(limits, sim.energy().total());
  ASSERT_EQ(guard.check(sim, 0.0), "");
  sim.particles().x[5].z() = -0.01;  // through the wall
  sim.particles().x[9].z() = 40.5;   // above z_max
  sim.particles().x[11].x() = 2.5 * sim.box().lx;
  const std::string why = guard.check(sim, 0.0);
  EXPECT_TRUE(contains(why, "3 grain(s) left the box")) << why;
  EXPECT_TRUE(contains(why, "grain 5")) << why;
  EXPECT_EQ(guard.grains_lost(), 3);
}

TEST(RunGuard, AnOverlapAboveTheBoundStops) {
  Simulation sim = small_sim();
  sim.setup();
  GuardLimits limits;
  limits.max_overlap = 0.1;
  RunGuard guard(limits, sim.energy().total());
  Particles& p = sim.particles();
  // Grains 0 and 1 lifted 5 d above the bed, overlapping by 0.15 d.
  double top = 0;
  for (const Vec3& x : p.x) top = std::max(top, x.z());
  p.x[0] = Vec3(1, 1, top + 5);
  p.x[1] = p.x[0] + Vec3(p.radius[0] + p.radius[1] - 0.15, 0, 0);
  sim.rebuild_lists();
  sim.step();  // the contact is found and marked touching
  const std::string why = guard.check(sim, 0.0);
  EXPECT_TRUE(contains(why, "exceeds max_overlap = 0.1")) << why;
  EXPECT_NEAR(guard.max_overlap_seen(), 0.15, 0.01);
  // The wall counts too: a grain sunk 0.12 d into it.
  Simulation sim2 = small_sim();
  sim2.setup();
  RunGuard guard2(limits, sim2.energy().total());
  sim2.particles().x[2].z() = sim2.particles().radius[2] - 0.12;
  EXPECT_NEAR(max_wall_overlap(sim2.particles(), sim2.box()), 0.12, 1e-12);
  EXPECT_TRUE(contains(guard2.check(sim2, 0.0), "overlap 0.12 d")) << guard2.check(sim2, 0.0);
}

TEST(RunGuard, EnergyGainedBeyondTheWorkDoneStops) {
  Simulation sim = small_sim();
  sim.setup();
  const double e0 = sim.energy().total();
  RunGuard guard(GuardLimits{}, e0);
  const double grains = static_cast<double>(sim.particles().count(Species::Mobile));
  // Random velocities of 1 sqrt(gd): ~0.26 rho g d^4 per grain, under the bound of 1.
  randomize_velocities(sim.particles(), 1.0, 0.0, 3);
  double gain = sim.energy().total() - e0;
  ASSERT_LT(gain / grains, 1.0);
  EXPECT_EQ(guard.check(sim, 0.0), "");
  // 3 sqrt(gd): ~2.4 per grain, over it ...
  randomize_velocities(sim.particles(), 3.0, 0.0, 3);
  gain = sim.energy().total() - e0;
  ASSERT_GT(gain / grains, 1.0);
  const std::string why = guard.check(sim, 0.0);
  EXPECT_TRUE(contains(why, "energy of the grains grew")) << why;
  // ... unless the intruder did that much work on the grains.
  EXPECT_EQ(guard.check(sim, gain), "");
}

namespace {

// One impact of a grain (mass m) on an infinite mass at speed v with the Hertz law
// F = kn sqrt(reff) x^{3/2}, integrated with velocity Verlet: {largest overlap, duration}.
std::pair<double, double> integrate_impact(double kn, double m, double reff, double v) {
  const double k = kn * std::sqrt(reff);
  const double dt = 1e-7 / std::max(v, 1.0);
  double x = 0, u = v, t = 0, x_max = 0;
  double a = 0;
  while (true) {
    u += 0.5 * dt * a;
    x += dt * u;
    t += dt;
    if (x <= 0) break;
    a = -k * std::pow(x, 1.5) / m;
    u += 0.5 * dt * a;
    x_max = std::max(x_max, x);
  }
  return {x_max, t};
}

// A bed for the limits alone: an intruder of radius R and the smallest and largest grains.
Bed limits_bed(double kn, double R) {
  Bed bed;
  bed.contact = ContactParams{}.with_stiffness(kn);
  Particles& p = bed.state.particles;
  p.add(Vec3(1, 1, 1), 0.45, Species::Mobile);
  p.add(Vec3(3, 1, 1), 0.55, Species::Mobile);
  bed.intruder = static_cast<int>(p.add(Vec3(6, 1, 2), R, Species::Intruder));
  return bed;
}

}  // namespace

TEST(SpeedLimit, ImpactOverlapAndDurationMatchAnIntegratedImpact) {
  const Bed bed = limits_bed(2e4, 1.0);
  const SpeedLimits s = speed_limits(bed, 4e-4, 0.2, 0.1);
  for (double v : {0.5, 5.0, 30.0}) {
    const auto big = integrate_impact(2e4, s.m_large, s.reff_large, v);
    EXPECT_NEAR(s.impact_overlap(v), big.first, 1e-4 * big.first) << v;
    const auto small = integrate_impact(2e4, s.m_small, s.reff_small, v);
    EXPECT_NEAR(s.dt_for(v) * TimeStepPolicy::steps_per_collision_min, small.second, 1e-3 * small.second)
        << v;
  }
  // The limits are where each bound is met exactly.
  EXPECT_NEAR(s.impact_overlap(s.overlap), 0.1, 1e-12);
  EXPECT_NEAR(s.dt_for(s.resolution), 4e-4, 1e-15);
  EXPECT_NEAR(s.skin * 4e-4, 0.02, 1e-15);
}

TEST(SpeedLimit, TheLargestSpeedPassesAndAnyFasterIsRefused) {
  const Bed bed = limits_bed(2e4, 1.0);
  const SpeedLimits s = speed_limits(bed, 4e-4, 0.2, 0.1);
  EXPECT_NO_THROW(check_pull_speed(0.999 * s.fastest(), bed, 4e-4, 0.2, 0.1));
  try {
    check_pull_speed(1.001 * s.fastest(), bed, 4e-4, 0.2, 0.1);
    FAIL() << "a speed over the limit was accepted";
  } catch (const Error& e) {
    const std::string msg = e.what();
    EXPECT_TRUE(contains(msg, "'speed' = ")) << msg;
    EXPECT_TRUE(contains(msg, "max_overlap")) << msg;  // the binding bound at kn = 2e4
    EXPECT_TRUE(contains(msg, "the largest speed that works is")) << msg;
  }
}

TEST(SpeedLimit, ATimeStepBoundGivesTheTimeStepToUse) {
  // Stiff contacts and a large dt: the impact is not resolved, the overlap is fine.
  const Bed bed = limits_bed(2e8, 1.0);
  const double dt = 1e-4;
  const SpeedLimits s = speed_limits(bed, dt, 0.2, 0.1);
  ASSERT_LT(s.resolution, s.overlap);
  const double v = 2 * s.resolution;
  try {
    check_pull_speed(v, bed, dt, 0.2, 0.1);
    FAIL() << "an unresolved impact was accepted";
  } catch (const Error& e) {
    const std::string msg = e.what();
    EXPECT_TRUE(contains(msg, "less than 16 steps of dt")) << msg;
    const auto at = msg.find("pour the bed with dt <= ");
    ASSERT_NE(at, std::string::npos) << msg;
    const double dt_ok = std::stod(msg.substr(at + 24));
    // The time step it names works for this speed (to its 4 printed digits).
    EXPECT_NO_THROW(check_pull_speed(v, bed, 0.999 * dt_ok, 0.2, 0.1));
    EXPECT_THROW(check_pull_speed(v, bed, 1.01 * dt_ok, 0.2, 0.1), Error);
  }
}
