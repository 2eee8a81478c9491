#include <gtest/gtest.h>

#include "contact/contact_params.hpp"
#include "core/error.hpp"
#include "helpers.hpp"
#include "protocol/restitution.hpp"

using namespace granudrag;

TEST(TimeStep, CollisionTimeFormulaMatchesDirectIntegration) {
  for (double v : {0.01, 1.0, 10.0}) {
    const double m = 0.5 * sphere_mass(0.45), reff = 0.225;
    const double expected = hertz_collision(2e8, 0.0, m, reff, v).duration;
    EXPECT_NEAR(hertz_collision_time(2e8, m, reff, v), expected, 1e-3 * expected) << "v = " << v;
  }
}

TEST(TimeStep, DefaultForPaperStiffnessIsNearPaperValue) {
  const double dt = default_time_step(ContactParams{}, 0.45);
  EXPECT_GT(dt, 0.8e-5);  // the paper used 1e-5 for K_n = 2e8
  EXPECT_LT(dt, 1.2e-5);
  // Softer contacts: dt scales as K_n^-0.4.
  const double soft = default_time_step(ContactParams{}.with_stiffness(2e5), 0.45);
  EXPECT_NEAR(soft / dt, std::pow(1e-3, -0.4), 1e-9);
}

TEST(TimeStep, TooLargeIsRefusedWithAWorkingValue) {
  const ContactParams p;
  try {
    check_time_step(1e-3, p, 0.45);
    FAIL() << "dt = 1e-3 accepted for K_n = 2e8";
  } catch (const Error& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("dt <="), std::string::npos) << msg;
    EXPECT_NE(msg.find("kn"), std::string::npos) << msg;
  }
  EXPECT_NO_THROW(check_time_step(1e-5, p, 0.45));
  EXPECT_THROW(check_time_step(-1e-5, p, 0.45), Error);
  EXPECT_THROW(check_time_step(NAN, p, 0.45), Error);
}

TEST(TimeStep, SimulationRefusesTooLargeStep) {
  LatticeBed bed = fcc_bed(50, 1);
  Settings s;
  s.dt = 1e-3;
  EXPECT_THROW(Simulation(bed.particles, bed.box, ContactParams{}, s), Error);
  s.dt = 0;  // derived
  Simulation sim(bed.particles, bed.box, ContactParams{}, s);
  EXPECT_DOUBLE_EQ(sim.dt(), default_time_step(ContactParams{}, bed.particles.min_radius(Species::Mobile)));
}
