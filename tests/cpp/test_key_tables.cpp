// The key tables bound to PourSpec, PullSpec and ContactParams (core/parameter_table.hpp): every bound key
// reads into its field, its field is checked against the key's range by the struct's validate(), and a row's
// default is its field's initial value.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "contact/contact_keys.hpp"
#include "core/error.hpp"
#include "core/parameter_table.hpp"
#include "protocol/placement.hpp"
#include "protocol/pour.hpp"
#include "protocol/pull.hpp"

using namespace granudrag;

namespace {

using Type = ParameterSpec::Type;

bool bounded_below(const ParameterSpec& s) { return s.min != -ParameterSpec::unbounded; }
bool bounded_above(const ParameterSpec& s) { return s.max != ParameterSpec::unbounded; }

// A value inside the row's range that is not its default, as the command line writes it.
std::string valid_value(const ParameterSpec& s) {
  if (s.type == Type::Flag) return s.default_value == "true" ? "false" : "true";
  const double lo = bounded_below(s) ? s.min : 0;
  const double step = bounded_above(s) ? std::min(1.0, (s.max - lo) / 2) : 1.0;
  double v = bounded_below(s) || bounded_above(s) ? lo + step : 1.5;
  if (number_text(v) == s.default_value) v = lo + step / 2;
  if (s.type == Type::Integer)
    v = std::ceil(v) == std::stod(s.default_value) ? std::ceil(v) + 1 : std::ceil(v);
  return number_text(v);
}

// A value just outside the row's range, or "" for a row without one.
std::string invalid_value(const ParameterSpec& s) {
  if (bounded_below(s)) return number_text(s.min_exclusive ? s.min : s.min - 1);
  if (bounded_above(s)) return number_text(s.max_exclusive ? s.max : s.max + 1);
  return "";
}

// --key value for each row the table reads, with `values`.
std::vector<std::string> arguments(const std::map<std::string, std::string>& values) {
  std::vector<std::string> args;
  for (const auto& [key, value] : values) {
    args.push_back("--" + key);
    args.push_back(value);
  }
  return args;
}

template <class Spec>
std::map<std::string, std::string> valid_values(const KeyTable<Spec>& table) {
  std::map<std::string, std::string> values;
  for (const auto& row : table.rows())
    if (row.read) values[row.spec.key] = valid_value(row.spec);
  return values;
}

template <class Spec>
Spec read(const KeyTable<Spec>& table, const std::map<std::string, std::string>& values) {
  Parameters p("test", table.specs());
  p.apply_cli(arguments(values));
  Spec spec;
  table.read(p, spec);
  return spec;
}

// A pour places the intruder at the centre of the box unless told otherwise (as pour_command
// does): the table does not read intruder_x and intruder_y.
PourSpec placed(PourSpec s) {
  s.intruder_x = s.lx / 2;
  s.intruder_y = s.ly / 2;
  return s;
}

// `alternatives`: key -> the key it excludes (a pour takes depth or intruder_z). The first is left
// out of the valid set, and the second when the first is the one given an invalid value.
template <class Spec>
void expect_round_trip(const KeyTable<Spec>& table, Spec (*complete)(Spec),
                       const std::map<std::string, std::string>& alternatives = {}) {
  const std::map<std::string, std::string> values = valid_values(table);
  ASSERT_FALSE(values.empty());
  const Spec spec = read(table, values);
  for (const auto& row : table.rows())
    if (row.read) {
      EXPECT_EQ(row.text(spec), values.at(row.spec.key)) << row.spec.key;
      EXPECT_NE(row.text(spec), row.text(Spec{})) << row.spec.key << ": the value read is the default";
    }
  std::map<std::string, std::string> valid = values;
  for (const auto& [key, excluded] : alternatives) valid.erase(key);
  EXPECT_NO_THROW(complete(read(table, valid)).validate());

  int refused = 0;
  for (const auto& row : table.rows()) {
    if (!row.read) continue;
    const std::string bad = invalid_value(row.spec);
    if (bad.empty()) continue;
    std::map<std::string, std::string> with_bad = valid;
    if (alternatives.count(row.spec.key)) with_bad.erase(alternatives.at(row.spec.key));
    with_bad[row.spec.key] = bad;
    try {
      complete(read(table, with_bad)).validate();
      ADD_FAILURE() << row.spec.key << " = " << bad << " accepted";
    } catch (const Error& e) {
      const std::string msg = e.what();
      EXPECT_NE(msg.find("'" + row.spec.key + "' = "), std::string::npos) << msg;
      EXPECT_NE(msg.find("is out of range"), std::string::npos) << msg;
      ++refused;
    }
  }
  EXPECT_GT(refused, 10);
}

PullSpec as_is(PullSpec s) { return s; }

}  // namespace

TEST(KeyTables, EveryPourKeyReadsIntoItsFieldAndIsChecked) {
  expect_round_trip(pour_keys(), placed, {{"intruder_z", "depth"}});
}

TEST(KeyTables, EveryPullKeyReadsIntoItsFieldAndIsChecked) { expect_round_trip(pull_keys(), as_is); }

TEST(KeyTables, TheDefaultsAreTheStructsAndEveryKeyIsBoundOrSaysWhy) {
  const PourSpec pour = read(pour_keys(), {});
  for (const auto& row : pour_keys().rows())
    if (row.read) {
      EXPECT_EQ(row.text(pour), row.text(PourSpec{})) << row.spec.key;
    }
  const PullSpec pull = read(pull_keys(), {});
  for (const auto& row : pull_keys().rows())
    if (row.read) {
      EXPECT_EQ(row.text(pull), row.text(PullSpec{})) << row.spec.key;
    }
  EXPECT_EQ(find_spec(pull_keys(), "sample_interval").default_value, "0.02");
  EXPECT_EQ(find_spec(pour_keys(), "ke_threshold").default_value, "1e-7");
  EXPECT_EQ(find_spec(pour_keys(), "depth").default_value, "");  // NaN: optional

  // The rows the commands read themselves, each with its reason in the table's comments.
  std::vector<std::string> unread;
  for (const auto& row : pour_keys().rows())
    if (!row.read) unread.push_back("pour." + row.spec.key);
  for (const auto& row : pull_keys().rows())
    if (!row.read) unread.push_back("pull." + row.spec.key);
  for (const auto& row : placement_keys().rows())
    if (!row.read) unread.push_back("place." + row.spec.key);
  EXPECT_EQ(unread, (std::vector<std::string>{"pour.intruder_x", "pour.intruder_y", "pull.speed",
                                              "pull.froude", "pull.active_diameters", "place.intruder_x",
                                              "place.intruder_y", "place.ke_threshold"}));
  const PlacementSpec place = read(placement_keys(), {});
  for (const auto& row : placement_keys().rows())
    if (row.read) {
      EXPECT_EQ(row.text(place), row.text(PlacementSpec{})) << row.spec.key;
    }
}

// Optional number keys bound to a NaN field: the pour's dt (NaN: from the Hertz collision time)
// and the pull's collision_steps (NaN: the bed's dt). Read when given, left NaN otherwise, and
// checked only when set.
TEST(KeyTables, TheTimeStepKeysAreOptionalFields) {
  EXPECT_TRUE(std::isnan(PourSpec{}.dt));
  EXPECT_TRUE(std::isnan(PullSpec{}.collision_steps));
  EXPECT_EQ(find_spec(pour_keys(), "dt").default_value, "");
  EXPECT_EQ(find_spec(pull_keys(), "collision_steps").default_value, "");
  EXPECT_EQ(find_spec(pour_keys(), "dt").help, time_step_key().help);  // one row, shared

  EXPECT_TRUE(std::isnan(read(pour_keys(), {}).dt));
  EXPECT_EQ(read(pour_keys(), {{"dt", "2.5e-4"}}).dt, 2.5e-4);
  EXPECT_TRUE(std::isnan(read(pull_keys(), {}).collision_steps));
  EXPECT_EQ(read(pull_keys(), {{"collision_steps", "32"}}).collision_steps, 32);

  PourSpec pour = placed(read(pour_keys(), {{"depth", "3"}}));
  EXPECT_NO_THROW(pour.validate());  // NaN: not checked
  PullSpec pull;
  EXPECT_NO_THROW(pull.validate());
  auto refusal = [](const auto& spec) {
    try {
      spec.validate();
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  for (const double bad : {0.0, -1e-4}) {
    pour.dt = bad;
    const std::string msg = refusal(pour);
    EXPECT_NE(msg.find("'dt' = "), std::string::npos) << bad << ": " << msg;
    EXPECT_NE(msg.find("is out of range: it must be > 0"), std::string::npos) << msg;
  }
  pull.collision_steps = 8;
  const std::string msg = refusal(pull);
  EXPECT_NE(msg.find("'collision_steps' = 8"), std::string::npos) << msg;
  EXPECT_NE(msg.find("is out of range: it must be >= 16"), std::string::npos) << msg;
  pull.collision_steps = 16;
  EXPECT_NO_THROW(pull.validate());
}

TEST(KeyTables, ASpeedReadByTheCommandIsStillChecked) {
  PullSpec s;
  s.speed = 0;
  try {
    s.validate();
    FAIL() << "speed 0 accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("'speed' = 0 sqrt(g d) is out of range: it must be > 0 sqrt(g d)"),
              std::string::npos)
        << e.what();
  }
  EXPECT_EQ(find_spec(pull_keys(), "speed").default_value, "");  // froude may be given instead
}

TEST(KeyTables, ARowAndItsFieldMustAgree) {
  struct S {
    double x = 1;
    long n = 2;
    std::string name;
  };
  EXPECT_NO_THROW(Key::number("x").default_value("1.0").field(&S::x));
  EXPECT_THROW(Key::number("x").default_value("2").field(&S::x), std::logic_error);
  EXPECT_THROW(Key::integer("x").field(&S::x), std::logic_error);
  EXPECT_THROW(Key::number("n").field(&S::n), std::logic_error);
  EXPECT_EQ(Key::text("name").field(&S::name).spec.default_value, "");
  const KeyTable<S> table = {Key::number("x").at_most(5).field(&S::x), Key::integer("n").field(&S::n)};
  EXPECT_EQ(table.specs()[1].default_value, "2");
  S s;
  s.x = 6;
  EXPECT_THROW(table.check(s, "test settings"), Error);
  EXPECT_THROW(KeyTable<S>(table).add_before("no_such_key", {}), std::logic_error);
}

TEST(KeyTables, NumberTextIsHowAPersonWritesADefault) {
  EXPECT_EQ(number_text(0.02), "0.02");
  EXPECT_EQ(number_text(1e-7), "1e-7");
  EXPECT_EQ(number_text(2e8), "2e8");
  EXPECT_EQ(number_text(20), "20");
  EXPECT_EQ(number_text(100), "100");
  EXPECT_EQ(number_text(5e4), "5e4");
  EXPECT_EQ(number_text(0), "0");
  EXPECT_EQ(number_text(-1), "-1");
  EXPECT_EQ(number_text(9e18), "9e18");
  EXPECT_EQ(number_text(1.225), "1.225");
}

TEST(KeyTables, EveryContactFieldIsAKeyAndValidateChecksItsRange) {
  // Every field of the contact law has its row (the struct holds doubles only, so a field without
  // one makes it larger than its rows); the rows without one say why (contact_keys.cpp). Derived
  // from the table, not listed here, so that adding a contact key touches no test
  // (docs/engine.md, "Adding a contact key").
  std::vector<std::string> bound, read_by_command;
  for (const auto& row : contact_keys().rows()) {
    if (row.number) bound.push_back(row.spec.key);
    if (row.number && !row.read) read_by_command.push_back(row.spec.key);
    EXPECT_EQ(bool(row.number), bool(row.set_number)) << row.spec.key;  // the bed file reads it back
  }
  EXPECT_EQ(bound.size() * sizeof(double), sizeof(ContactParams));
  // K_n's others follow it (contact_from); every other field is read by the table.
  EXPECT_EQ(read_by_command, (std::vector<std::string>{"kn", "kt", "gamman", "gammat"}));
  EXPECT_EQ(find_spec(contact_keys(), "mu").default_value, number_text(ContactParams{}.mu));
  EXPECT_EQ(find_spec(contact_keys(), "kn").default_value, "");

  EXPECT_NO_THROW(ContactParams{}.validate());
  for (const auto& row : contact_keys().rows()) {
    if (!row.set_number) continue;
    const std::string& key = row.spec.key;
    for (const double bad : {std::stod(invalid_value(row.spec)), double(NAN)}) {
      ContactParams c;
      row.set_number(c, bad);
      try {
        c.validate();
        ADD_FAILURE() << key << " = " << bad << " accepted";
      } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("'" + key + "' = "), std::string::npos) << e.what();
      }
    }
  }
}

TEST(KeyTables, ContactFieldsListEachBoundKeyWithItsFieldsValueAndDescribeWritesThem) {
  // contact_fields() is what a bed file stores, `info` prints and describe() writes: each key
  // bound to a field, in the table's order, with that field's own value (distinct values here,
  // so a key paired with another field's value fails).
  ContactParams c;
  int i = 0;
  for (const auto& row : contact_keys().rows())
    if (row.set_number) row.set_number(c, 1.5 + ++i);
  const auto fields = contact_fields(c);
  std::size_t j = 0;
  std::string text;
  for (const auto& row : contact_keys().rows()) {
    if (!row.number) continue;
    ASSERT_LT(j, fields.size()) << row.spec.key;
    EXPECT_EQ(fields[j].first, row.spec.key);
    EXPECT_EQ(fields[j].second, *row.number(c)) << row.spec.key;
    text += (text.empty() ? "" : " ") + row.spec.key + "=" + number_text(*row.number(c));
    ++j;
  }
  EXPECT_EQ(j, fields.size());
  EXPECT_EQ(fields.size(), static_cast<std::size_t>(i));
  EXPECT_EQ(fields.at(0).first, "kn");
  EXPECT_EQ(fields.at(0).second, c.kn);
  EXPECT_EQ(c.describe(), text);  // values of a few digits, which both write alike
}
