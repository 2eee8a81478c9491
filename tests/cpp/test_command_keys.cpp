// The key tables of the commands: PourSpec's and PullSpec's defaults are their keys' defaults,
// their validate() uses the keys' ranges, and `granudrag info` prints the library's numbers.
// The tables' binding to the structs: test_key_tables.cpp.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <string>

#include "app/command.hpp"
#include "core/error.hpp"
#include "core/parameters.hpp"
#include "protocol/pour.hpp"
#include "protocol/pull.hpp"

using namespace granudrag;

namespace {

// The number after "key": in a one-line JSON object.
double json_number(const std::string& json, const std::string& key) {
  const auto at = json.find("\"" + key + "\": ");
  if (at == std::string::npos) throw std::runtime_error("no '" + key + "' in " + json);
  return std::strtod(json.c_str() + at + key.size() + 4, nullptr);
}

std::string info(const std::vector<std::string>& args) {
  Parameters p("info", info_keys());
  p.apply_cli(args);
  p.validate();
  return info_json(p);
}

}  // namespace

TEST(CommandKeys, PourSpecDefaultsAreTheKeysDefaults) {
  const Parameters p("pour", pour_keys());
  const PourSpec s;
  EXPECT_EQ(p.number("lx"), s.lx);
  EXPECT_EQ(p.number("ly"), s.ly);
  EXPECT_EQ(p.integer("grains"), s.grains);
  EXPECT_EQ(p.number("intruder_diameter"), s.intruder_diameter);
  EXPECT_EQ(p.is_set("depth"), !std::isnan(s.depth));
  EXPECT_EQ(p.is_set("intruder_z"), !std::isnan(s.intruder_z));
  EXPECT_EQ(p.is_set("packing_estimate"), !std::isnan(s.packing_estimate));
  EXPECT_EQ(p.number("fill_fraction"), s.fill_fraction);
  EXPECT_EQ(p.number("ke_threshold"), s.ke_threshold);
  EXPECT_EQ(p.number("max_settle_time"), s.max_settle_time);
  EXPECT_EQ(p.number("check_interval"), s.check_interval);
  EXPECT_EQ(p.number("base_height"), s.base_height);
  EXPECT_EQ(static_cast<std::uint64_t>(p.integer("seed")), s.seed);
  EXPECT_EQ(p.number("skin"), s.skin);
}

TEST(CommandKeys, PullSpecDefaultsAreTheKeysDefaults) {
  const Parameters p("pull", pull_keys());
  const PullSpec s;
  EXPECT_FALSE(p.is_set("speed"));  // the command's default is PullSpec's 1 unless froude is given
  EXPECT_EQ(s.speed, 1.0);
  EXPECT_EQ(p.number("distance"), s.distance);
  EXPECT_EQ(p.number("sample_interval"), s.sample_interval);
  EXPECT_EQ(p.number("transient"), s.transient);
  EXPECT_EQ(p.number("shell"), s.shell);
  EXPECT_EQ(p.integer("snapshots"), s.snapshots);
  EXPECT_EQ(p.number("slab_half_width"), s.slab_half_width);
  EXPECT_EQ(p.number("skin"), s.skin);
  EXPECT_EQ(p.number("active_radius"), s.active.radius);
  EXPECT_FALSE(s.active.enabled());  // off unless asked for
  EXPECT_EQ(p.number("sleep_speed"), s.sleep_speed);
  EXPECT_EQ(p.number("sleep_speed_max"), s.sleep_speed_max);
  EXPECT_EQ(p.number("sleep_time"), s.active.sleep_time);
  // Unset: the pull takes default_wake_force(K_n) from the bed.
  EXPECT_FALSE(p.is_set("wake_force"));
  EXPECT_TRUE(std::isnan(s.active.wake_force));
}

TEST(CommandKeys, SpecValidateUsesTheKeysRanges) {
  PourSpec pour;
  pour.depth = 5;
  EXPECT_NO_THROW(pour.validate());
  pour.fill_fraction = 0.36;  // the row says (0, 0.35]
  try {
    pour.validate();
    FAIL() << "fill_fraction 0.36 accepted";
  } catch (const Error& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("'fill_fraction' = 0.36 is out of range: it must be in (0, 0.35]"), std::string::npos)
        << msg;
  }
  pour.fill_fraction = 0.3;
  pour.lx = 3;  // >= 4
  EXPECT_THROW(pour.validate(), Error);
  pour.lx = 20;
  pour.intruder_x = 20;  // a cross-key invariant: inside the box
  EXPECT_THROW(pour.validate(), Error);
  pour.intruder_x = 10;
  pour.intruder_z = 3;  // and depth
  EXPECT_THROW(pour.validate(), Error);

  PullSpec pull;
  EXPECT_NO_THROW(pull.validate());
  pull.snapshots = 1001;
  EXPECT_THROW(pull.validate(), Error);
  pull.snapshots = 3;
  pull.speed = NAN;
  EXPECT_THROW(pull.validate(), Error);
}

TEST(CommandKeys, APullStepsAtTheBedsDtUnlessCollisionStepsIsSet) {
  Bed bed;
  bed.contact = ContactParams{}.with_stiffness(2e4);
  bed.state.particles.add(Vec3(1, 1, 1), 0.5, Species::Mobile);
  bed.state.particles.add(Vec3(3, 1, 1), 0.46, Species::Mobile);
  bed.state.particles.add(Vec3(5, 1, 1), 0.4, Species::Frozen);  // the base's grains do not count
  bed.dt = 1e-3;
  PullSpec spec;
  EXPECT_EQ(pull_time_step(spec, bed), 1e-3);  // NaN: the bed's, as poured
  spec.collision_steps = 32;
  EXPECT_EQ(pull_time_step(spec, bed), shortest_collision_time(bed.contact, 0.46) / 32);
  spec.collision_steps = 8;  // coarser than check_time_step allows
  EXPECT_THROW(pull_time_step(spec, bed), Error);
}

TEST(CommandKeys, InfoPrintsTheLibrarysNumbers) {
  const std::string json = info({"--kn", "2e4", "--intruder_diameter", "3", "--froude", "0.7"});
  const ContactParams c = ContactParams{}.with_stiffness(2e4);
  EXPECT_EQ(json_number(json, "kn"), c.kn);
  EXPECT_EQ(json_number(json, "kt"), c.kt);
  EXPECT_EQ(json_number(json, "gamman"), c.gamman);
  EXPECT_EQ(json_number(json, "gammat"), c.gammat);
  EXPECT_EQ(json_number(json, "mu"), c.mu);
  EXPECT_EQ(json_number(json, "dt"), default_time_step(c, 0.45));
  EXPECT_EQ(json_number(json, "collision_time"), shortest_collision_time(c, 0.45));
  EXPECT_EQ(json_number(json, "max_dt"),
            shortest_collision_time(c, 0.45) / TimeStepPolicy::steps_per_collision_min);
  EXPECT_EQ(json_number(json, "intruder_diameter"), 3.0);
  const double V = json_number(json, "speed");
  EXPECT_EQ(V, 0.7 / froude_number(1.0, 3.0));
  EXPECT_EQ(json_number(json, "froude"), froude_number(V, 3.0));
  EXPECT_NEAR(json_number(json, "froude"), 0.7, 1e-15);

  // The speed given instead; the time step given; Young's modulus.
  const std::string by_speed = info({"--intruder_diameter", "2", "--speed", "0.25", "--dt", "1e-6"});
  EXPECT_EQ(json_number(by_speed, "froude"), froude_number(0.25, 2.0));
  EXPECT_EQ(json_number(by_speed, "dt"), 1e-6);
  EXPECT_EQ(json_number(by_speed, "kn"), ContactParams{}.kn);
  const std::string young = info({"--youngs_modulus", "1e6", "--poisson_ratio", "0.25"});
  const ContactParams y = ContactParams::from_young(1e6, 0.25, 0, 0, 0);
  EXPECT_EQ(json_number(young, "kn"), y.kn);
  EXPECT_EQ(json_number(young, "kt"), y.kt);
  EXPECT_EQ(json_number(young, "gamman"), 5e4 * std::pow(y.kn / 2e8, 0.6));
  EXPECT_EQ(json.find("\"speed\""), json.rfind("\"speed\""));  // each key once

  EXPECT_THROW(info({"--dt", "1"}), Error);                 // larger than max_dt
  EXPECT_THROW(info({"--intruder_diameter", "2"}), Error);  // no speed
  EXPECT_THROW(info({"--froude", "1"}), Error);             // no diameter
  EXPECT_THROW(info({"--intruder_diameter", "2", "--speed", "1", "--froude", "1"}), Error);
}
