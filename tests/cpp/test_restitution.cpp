// Paper Fig. 2: a grain hitting the wall. The engine's e(v_n) against a direct high-accuracy
// integration of the viscoelastic Hertz equation (hertz_collision: RK4 on the two-body ODE,
// sharing nothing with the engine but the parameters), and the invariance of e(v_n) when
// gamma_n / K_n^0.6 is held fixed (paper Sec. III I).
#include <gtest/gtest.h>

#include "helpers.hpp"
#include "protocol/restitution.hpp"

using namespace granudrag;

namespace {
const double kSpeeds[] = {0.01, 0.03, 0.1, 0.3, 1.0, 3.0, 10.0};
double simulated_restitution(const ContactParams& c, double v) { return dem_restitution(c, v); }
double theory(double kn, double gamman, double v) {
  return hertz_collision(kn, gamman, sphere_mass(0.5), 0.5, v).restitution;
}
}  // namespace

TEST(Restitution, ReferenceIntegratorConservesEnergyWithoutDamping) {
  // The oracle checks itself: no damping, e = 1.
  const auto r = hertz_collision(2e8, 0.0, sphere_mass(0.5), 0.5, 1.0);
  EXPECT_NEAR(r.restitution, 1.0, 1e-6);
}

class RestitutionVsTheory : public ::testing::TestWithParam<double> {};

TEST_P(RestitutionVsTheory, WithinOnePercentOfDirectIntegration) {
  const ContactParams c = ContactParams{}.with_stiffness(GetParam());
  for (double v : kSpeeds) {
    const double expected = theory(c.kn, c.gamman, v);
    const double got = simulated_restitution(c, v);
    EXPECT_NEAR(got, expected, 0.01 * expected) << "K_n = " << c.kn << ", v_n = " << v;
    EXPECT_LT(expected, 1.0);
    EXPECT_GT(expected, 0.0);
  }
}

// The paper's K_n = 2e8 and a softened set (K_n = 2e5, gamma_n scaled by (1e-3)^0.6).
INSTANTIATE_TEST_SUITE_P(PaperAndSoft, RestitutionVsTheory, ::testing::Values(2.0e8, 2.0e5));

TEST(Restitution, UnchangedWhenDampingScalesAsStiffnessToThePowerPointSix) {
  const ContactParams paper;
  const ContactParams soft = paper.with_stiffness(2.0e5);
  ContactParams wrong = soft;  // gamma_n off the K_n^0.6 scaling: e must change
  wrong.gamman = 2.0 * soft.gamman;
  for (double v : {0.1, 1.0, 10.0}) {
    const double e_paper = simulated_restitution(paper, v);
    EXPECT_NEAR(simulated_restitution(soft, v), e_paper, 0.01 * e_paper) << "v_n = " << v;
    EXPECT_GT(std::abs(theory(wrong.kn, wrong.gamman, v) - e_paper), 0.05);
  }
  // e decreases with impact speed (paper Fig. 2).
  EXPECT_GT(simulated_restitution(paper, 0.1), simulated_restitution(paper, 10.0));
}
