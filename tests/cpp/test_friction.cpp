// Friction against analytic answers. A sphere on a plane tilted by theta (gravity tilted
// instead) rolls without slipping, the contact point sticking, while tan(theta) < 7 mu / 2, with
// acceleration (5/7) g sin(theta); beyond that it slides with g (sin(theta) - mu cos(theta)) and
// spins up at 5 mu g cos(theta) / (2 R). (For a sphere the threshold is 7 mu / 2, not mu: a
// sphere rolls rather than sticks.) The plane is the wall and, separately, the
// top of a frozen grain so large that it is flat where the sphere rolls.
#include <gtest/gtest.h>

#include <cmath>

#include "helpers.hpp"

using namespace granudrag;

namespace {

struct Motion {
  double accel;        // mean acceleration along the slope
  double slip;         // |v - R omega| at the contact at the end
  double worst_ratio;  // max over steps of |F_t| / (mu |F_n|)
  double spin_accel;
};

enum class Surface { Wall, FrozenGrain };

// The plane is either the wall or the top of a frozen grain of radius 400 (flat to 1e-4 over
// the distance rolled), which exercises the grain path with a frozen partner (m_eff = m_i).
Motion roll_down(double mu, double tan_theta, Surface surface = Surface::Wall) {
  const double theta = std::atan(tan_theta), R = 0.5, R_big = 400.0;
  ContactParams c = support::soft_params(mu);
  Particles p;
  const double m = sphere_mass(R);
  const double reff = surface == Surface::Wall ? R : R * R_big / (R + R_big);
  const double delta = std::pow(m * std::cos(theta) / (c.kn * std::sqrt(reff)), 2.0 / 3.0);
  Box box{10, 10, true};
  Vec3 centre(5, 5, 0);  // centre of curvature of the surface under the grain
  if (surface == Surface::FrozenGrain) {
    box = Box{1700, 1700, false};
    centre = Vec3(850, 850, 0);
    p.add(centre, R_big, Species::Frozen);
  }
  const double lift = surface == Surface::Wall ? 0.0 : R_big;
  p.add(centre + Vec3(0, 0, lift + R - delta), R, Species::Mobile);
  const std::size_t ball = p.size() - 1;
  Settings s;
  s.gravity = Vec3(std::sin(theta), 0, -std::cos(theta));
  Simulation sim(p, box, c, s);
  Motion out{0, 0, 0, 0};
  const long steps = 3000;
  const double t_start = 0.05;  // let the normal oscillation of the start die down
  Vec3 v_start = Vec3::Zero(), w_start = Vec3::Zero();
  for (long k = 0; k < steps; ++k) {
    sim.step();
    const Particles& q = sim.particles();
    const Vec3 contact = q.f[ball] - m * s.gravity;  // the surface's force on the grain
    const Vec3 n = surface == Surface::Wall ? Vec3(0, 0, 1) : Vec3((q.x[ball] - centre).normalized());
    const double fn = contact.dot(n), ft = (contact - fn * n).norm();
    if (mu > 0 && fn > 0) out.worst_ratio = std::max(out.worst_ratio, ft / (mu * fn));
    if (std::abs(sim.time() - t_start) < 0.5 * sim.dt()) {
      v_start = q.v[ball];
      w_start = q.omega[ball];
    }
  }
  const Particles& q = sim.particles();
  const double T = sim.time() - t_start;
  out.accel = (q.v[ball].x() - v_start.x()) / T;
  out.spin_accel = (q.omega[ball].y() - w_start.y()) / T;
  out.slip = std::abs(q.v[ball].x() - R * q.omega[ball].y());
  return out;
}

class FrictionOn : public ::testing::TestWithParam<Surface> {};

TEST_P(FrictionOn, RollsWithoutSlipBelowThreshold) {
  const double mu = 0.4, tan_theta = 1.0;  // below 7 mu / 2 = 1.4
  const Motion m = roll_down(mu, tan_theta, GetParam());
  const double theta = std::atan(tan_theta);
  const double expected = 5.0 / 7.0 * std::sin(theta);
  EXPECT_NEAR(m.accel, expected, 0.01 * expected);
  EXPECT_LT(m.slip, 1e-3 * std::abs(m.accel));  // contact point sticks
  EXPECT_LE(m.worst_ratio, 1.0 + 1e-12);
}

TEST_P(FrictionOn, SlidesAboveThresholdAtTheCoulombLimit) {
  const double mu = 0.2, tan_theta = 1.0;  // above 7 mu / 2 = 0.7
  const Motion m = roll_down(mu, tan_theta, GetParam());
  const double theta = std::atan(tan_theta);
  const double expected = std::sin(theta) - mu * std::cos(theta);
  EXPECT_NEAR(m.accel, expected, 0.01 * expected);
  EXPECT_NEAR(m.spin_accel, 5 * mu * std::cos(theta) / (2 * 0.5), 0.01 * 5 * mu * std::cos(theta));
  EXPECT_GT(m.slip, 0.1);
  EXPECT_LE(m.worst_ratio, 1.0 + 1e-12);  // |F_t| <= mu |F_n| at every step
  EXPECT_GT(m.worst_ratio, 1.0 - 1e-9);   // ... and it sits on the limit
}

TEST_P(FrictionOn, FrictionlessSphereSlidesWithoutSpinning) {
  const Motion m = roll_down(0.0, 0.5, GetParam());
  const double expected = std::sin(std::atan(0.5));
  EXPECT_NEAR(m.accel, expected, 1e-3 * expected);
  EXPECT_NEAR(m.spin_accel, 0.0, 1e-12);
}

INSTANTIATE_TEST_SUITE_P(WallAndFrozenGrain, FrictionOn,
                         ::testing::Values(Surface::Wall, Surface::FrozenGrain));

}  // namespace
