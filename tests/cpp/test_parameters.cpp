#include <gtest/gtest.h>
#include <unistd.h>

#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <initializer_list>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "core/parameters.hpp"

using namespace granudrag;
using Type = ParameterSpec::Type;

namespace {

constexpr double inf = ParameterSpec::unbounded;

// A spec list with every type, both kinds of bound, a dotted key, a unit with non-ASCII
// characters and a required key, shaped like `granudrag pour`.
std::vector<ParameterSpec> pour_specs() {
  return {
      Key::integer("grains").default_value("20000").at_least(1).help("number of grains"),
      Key::number("friction").default_value("0.5").at_least(0).help("friction coefficient"),
      Key::number("dt").unit("√(d/g)").above(0).help("time step"),
      Key::number("poisson").default_value("0.3").above(-1).below(0.5).help("Poisson's ratio"),
      Key::text("output").required().help("run file to write"),
      Key::text("label").default_value("bed").help("free text"),
      Key::numbers("speeds").unit("√(gd)").default_value("0.1,1,10").above(0).help("pulling speeds"),
      Key::flag("quiet").help("no progress lines"),
      Key::number("contact.kn").unit("ρdg").default_value("2e8").above(0).help("normal stiffness"),
  };
}

Parameters pour() { return Parameters("pour", pour_specs()); }

// A YAML file under the temp directory, unique to this process and call, removed at scope end.
class TempFile {
 public:
  explicit TempFile(const std::string& content, const std::string& stem = "pour") {
    static std::atomic<int> counter{0};
    path_ = (std::filesystem::temp_directory_path() / ("granudrag_test_" + std::to_string(::getpid()) + "_" +
                                                       std::to_string(counter++) + "_" + stem + ".yaml"))
                .string();
    std::ofstream(path_) << content;
  }
  ~TempFile() {
    std::error_code ec;
    std::filesystem::remove(path_, ec);
  }
  TempFile(const TempFile&) = delete;
  TempFile& operator=(const TempFile&) = delete;
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

// Runs `f`, which must throw granudrag::Error whose message contains every one of `parts`.
void expect_error(const std::function<void()>& f, std::initializer_list<std::string> parts) {
  try {
    f();
    ADD_FAILURE() << "no granudrag::Error thrown";
  } catch (const Error& e) {
    const std::string msg = e.what();
    for (const auto& part : parts)
      EXPECT_NE(msg.find(part), std::string::npos) << "'" << part << "' missing from: " << msg;
  }
}

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

}  // namespace

TEST(Parameters, Defaults) {
  const Parameters p = pour();
  EXPECT_EQ(p.integer("grains"), 20000);
  EXPECT_EQ(p.number("friction"), 0.5);
  EXPECT_EQ(p.number("poisson"), 0.3);
  EXPECT_EQ(p.number("contact.kn"), 2e8);
  EXPECT_EQ(p.text("label"), "bed");
  EXPECT_EQ(p.numbers("speeds"), (std::vector<double>{0.1, 1, 10}));
  EXPECT_FALSE(p.flag("quiet"));
  EXPECT_TRUE(p.is_set("quiet"));
  EXPECT_FALSE(p.is_set("dt"));
  EXPECT_FALSE(p.is_set("output"));
  // The only missing value is the required one.
  expect_error([&] { p.validate(); }, {"'output'", "required", "--output"});
}

TEST(Parameters, YamlLoad) {
  TempFile f(
      "# a pour\n"
      "grains: 1e5\n"        // integers may be written in exponent form
      "friction: \"0.3\"\n"  // numbers may be quoted
      "dt: 2.5e-6\n"
      "output: bed.h5\n"
      "label: 42\n"  // text stays text
      "speeds: [0.5, 2]\n"
      "quiet: yes\n"
      "poisson: ~\n"  // null: not given, the default stays
      "contact:\n"
      "  kn: 2e5\n");  // nested mapping = dotted key
  Parameters p = pour();
  p.load_yaml(f.path());
  EXPECT_EQ(p.integer("grains"), 100000);
  EXPECT_EQ(p.number("friction"), 0.3);
  EXPECT_EQ(p.number("dt"), 2.5e-6);
  EXPECT_EQ(p.text("output"), "bed.h5");
  EXPECT_EQ(p.text("label"), "42");
  EXPECT_EQ(p.numbers("speeds"), (std::vector<double>{0.5, 2}));
  EXPECT_TRUE(p.flag("quiet"));
  EXPECT_EQ(p.number("poisson"), 0.3);
  EXPECT_EQ(p.number("contact.kn"), 2e5);
  EXPECT_NO_THROW(p.validate());
}

TEST(Parameters, YamlDottedKeyAndScalarList) {
  TempFile f("contact.kn: 3e5\nspeeds: 1,2,3\n");
  Parameters p = pour();
  p.load_yaml(f.path());
  EXPECT_EQ(p.number("contact.kn"), 3e5);
  EXPECT_EQ(p.numbers("speeds"), (std::vector<double>{1, 2, 3}));
}

TEST(Parameters, EmptyYamlSetsNothing) {
  TempFile f("# nothing yet\n");
  Parameters p = pour();
  p.load_yaml(f.path());
  EXPECT_EQ(p.integer("grains"), 20000);
}

TEST(Parameters, CliOverridesYamlRegardlessOfOrder) {
  TempFile f("grains: 500\nfriction: 0.3\noutput: from_yaml.h5\n");
  const std::vector<std::vector<std::string>> orders = {
      {"--friction", "0.7", "--config", f.path()},
      {"--config", f.path(), "--friction", "0.7"},
      {"--friction=0.7", "--config=" + f.path()},
  };
  for (const auto& args : orders) {
    Parameters p = pour();
    p.apply_cli(args);
    EXPECT_EQ(p.number("friction"), 0.7) << args[0];
    EXPECT_EQ(p.integer("grains"), 500) << args[0];
    EXPECT_EQ(p.text("output"), "from_yaml.h5") << args[0];
  }
  // Also when the caller loads the file after the command line.
  Parameters p = pour();
  p.apply_cli({"--friction", "0.7"});
  p.load_yaml(f.path());
  EXPECT_EQ(p.number("friction"), 0.7);
  EXPECT_EQ(p.integer("grains"), 500);
}

TEST(Parameters, ConfigFilesApplyInOrder) {
  TempFile base("grains: 500\nfriction: 0.3\n"), study("friction: 0.4\n");
  Parameters p = pour();
  p.apply_cli({"--config", base.path(), "--config", study.path()});
  EXPECT_EQ(p.integer("grains"), 500);
  EXPECT_EQ(p.number("friction"), 0.4);
}

TEST(Parameters, CliForms) {
  Parameters p = pour();
  p.apply_cli(
      {"--quiet", "--poisson", "-0.2", "--speeds", "1, 2,3", "--output", "x.h5", "--contact.kn", "2e5"});
  EXPECT_TRUE(p.flag("quiet"));
  EXPECT_EQ(p.number("poisson"), -0.2);
  EXPECT_EQ(p.numbers("speeds"), (std::vector<double>{1, 2, 3}));
  EXPECT_EQ(p.text("output"), "x.h5");
  EXPECT_EQ(p.number("contact.kn"), 2e5);

  Parameters q = pour();
  q.apply_cli({"--quiet", "false", "--grains", "300"});
  EXPECT_FALSE(q.flag("quiet"));
  EXPECT_EQ(q.integer("grains"), 300);
  Parameters r = pour();
  r.apply_cli({"--grains", "300", "--quiet"});  // a flag last, with nothing after it
  EXPECT_TRUE(r.flag("quiet"));
}

TEST(Parameters, YamlErrorsNameFileAndKey) {
  Parameters p = pour();
  const std::string missing =
      (std::filesystem::temp_directory_path() / "granudrag_no_such_file_pour.yaml").string();
  expect_error([&] { p.load_yaml(missing); }, {missing, "does not exist"});

  TempFile syntax("grains: 10\nfriction: 0.5\nlabel: a: b\n", "syntax");
  expect_error([&] { p.load_yaml(syntax.path()); }, {syntax.path(), "line 3", "syntax"});

  TempFile list("- 1\n- 2\n", "list");
  expect_error([&] { p.load_yaml(list.path()); }, {list.path(), "mapping", "a list"});

  TempFile typo("grains: 10\nfrition: 0.3\n", "typo");
  expect_error([&] { p.load_yaml(typo.path()); },
               {"unknown key 'frition'", typo.path(), "line 2", "did you mean 'friction'?"});

  TempFile wrong("grains: many\n", "wrong");
  expect_error([&] { p.load_yaml(wrong.path()); },
               {"'grains' must be an integer, got 'many'", wrong.path(), "line 1"});

  TempFile fraction("grains: 2.5\n", "fraction");
  expect_error([&] { p.load_yaml(fraction.path()); }, {"'grains'", "integer", "2.5"});

  TempFile flag("quiet: maybe\n", "flag");
  expect_error([&] { p.load_yaml(flag.path()); }, {"'quiet'", "true or false", flag.path()});

  TempFile seq("friction: [1, 2]\n", "seq");
  expect_error([&] { p.load_yaml(seq.path()); }, {"'friction'", "a number", seq.path()});

  TempFile badlist("speeds: [1, fast]\n", "badlist");
  expect_error([&] { p.load_yaml(badlist.path()); }, {"'speeds'", "list of numbers", "fast"});

  TempFile twice("grains: 10\ngrains: 20\n", "twice");
  expect_error([&] { p.load_yaml(twice.path()); }, {"'grains'", "twice", "lines 1 and 2"});

  TempFile nested("contact:\n  kx: 1\n", "nested");
  expect_error([&] { p.load_yaml(nested.path()); },
               {"'contact.kx'", nested.path(), "did you mean 'contact.kn'?"});

  // A bad file leaves every value as it was, including those before the bad line.
  TempFile partial("grains: 10\nfriction: lots\n", "partial");
  EXPECT_THROW(p.load_yaml(partial.path()), Error);
  EXPECT_EQ(p.integer("grains"), 20000);
}

TEST(Parameters, CliErrorsNameOptionAndSuggest) {
  Parameters p = pour();
  expect_error(
      [&] {
        p.apply_cli({"--frition", "0.3"});
      },
      {"'--frition'", "did you mean '--friction'?", "--help"});
  expect_error([&] { p.apply_cli({"--contact-kn", "1"}); }, {"did you mean '--contact.kn'?"});
  expect_error([&] { p.apply_cli({"--grains"}); }, {"'--grains'", "needs a value"});
  expect_error([&] { p.apply_cli({"--grains", "--quiet"}); }, {"'--grains'", "needs a value"});
  expect_error(
      [&] {
        p.apply_cli({"--grains", "many"});
      },
      {"'grains' must be an integer, got 'many'", "command line"});
  expect_error([&] { p.apply_cli({"--friction", "inf"}); }, {"'friction'", "a number"});
  expect_error([&] { p.apply_cli({"--quiet", "maybe"}); }, {"'quiet'", "true or false"});
  expect_error([&] { p.apply_cli({"--speeds", "1,,2"}); }, {"'speeds'", "list of numbers"});
  expect_error([&] { p.apply_cli({"stray"}); }, {"unexpected argument 'stray'"});
  expect_error([&] { p.apply_cli({"--grains", "1", "--grains", "2"}); }, {"'--grains'", "twice"});
  expect_error([&] { p.apply_cli({"--config"}); }, {"--config"});

  // A bad --config file is reported, and nothing is applied.
  TempFile typo("frition: 0.3\n", "typo");
  expect_error(
      [&] {
        p.apply_cli({"--grains", "7", "--config", typo.path()});
      },
      {typo.path(), "'frition'", "did you mean 'friction'?"});
  EXPECT_EQ(p.integer("grains"), 20000);
}

TEST(Parameters, RangeChecksAtBothBounds) {
  const auto check = [](const std::vector<std::string>& args) {
    Parameters p = pour();
    std::vector<std::string> all{"--output", "x.h5"};
    all.insert(all.end(), args.begin(), args.end());
    p.apply_cli(all);
    p.validate();
  };
  // Inclusive minimum: 0 is allowed, just below is not.
  EXPECT_NO_THROW(check({"--friction", "0"}));
  expect_error(
      [&] {
        check({"--friction", "-0.1"});
      },
      {"'friction' = -0.1 is out of range: it must be >= 0", "friction coefficient",
       "--friction on the command line"});
  // Exclusive minimum: 0 is refused, the smallest positive double is not.
  EXPECT_NO_THROW(check({"--dt", "5e-324"}));
  expect_error([&] { check({"--dt", "0"}); }, {"'dt' = 0 √(d/g)", "> 0 √(d/g)"});
  // Both bounds, exclusive at both ends here.
  EXPECT_NO_THROW(check({"--poisson", "0.49999"}));
  EXPECT_NO_THROW(check({"--poisson", "-0.99999"}));
  expect_error([&] { check({"--poisson", "0.5"}); }, {"'poisson' = 0.5", "in (-1, 0.5)"});
  expect_error([&] { check({"--poisson", "-1"}); }, {"'poisson' = -1", "in (-1, 0.5)"});
  // Integers and list items.
  EXPECT_NO_THROW(check({"--grains", "1"}));
  expect_error([&] { check({"--grains", "0"}); }, {"'grains' = 0", ">= 1"});
  expect_error([&] { check({"--speeds", "1,0,2"}); }, {"'speeds'", "item 2 is 0", "> 0"});

  // All problems at once, the YAML source named.
  TempFile f("friction: -1\ngrains: 0\n");
  Parameters p = pour();
  p.load_yaml(f.path());
  expect_error([&] { p.validate(); },
               {"3 problems", "'friction' = -1", "'grains' = 0", "'output'", f.path()});
}

TEST(Parameters, AccessorsGuardTheirUse) {
  const Parameters p = pour();
  EXPECT_THROW(p.number("no_such_key"), std::logic_error);
  EXPECT_THROW(p.is_set("no_such_key"), std::logic_error);
  EXPECT_THROW(p.number("grains"), std::logic_error);                 // an integer
  EXPECT_THROW(p.integer("friction"), std::logic_error);              // a number
  expect_error([&] { p.text("output"); }, {"'output'", "--output"});  // declared, no value
}

TEST(Parameters, SpecBugsAreLogicErrors) {
  const auto with = [](ParameterSpec extra) {
    auto specs = pour_specs();
    specs.push_back(std::move(extra));
    return Parameters("pour", specs);
  };
  EXPECT_THROW(with(Key::integer("grains").default_value("1")), std::logic_error);  // twice
  EXPECT_THROW(with(Key::text("config")), std::logic_error);                        // reserved
  EXPECT_THROW(with(Key::text("schema")), std::logic_error);                        // reserved
  EXPECT_THROW(with(Key::text("bad key")), std::logic_error);
  EXPECT_THROW(with(Key::integer("n").default_value("lots")), std::logic_error);
  EXPECT_THROW(with(Key::number("x").default_value("-1").at_least(0)), std::logic_error);  // out of range
  EXPECT_THROW(with(Key::number("y").default_value("1").required()), std::logic_error);    // required
  EXPECT_THROW(with(Key::number("z").default_value("1").above(1)), std::logic_error);      // exclusive
  EXPECT_THROW(with(Key::number("w").default_value("0.5").below(0.5)), std::logic_error);
}

TEST(Parameters, ToYamlRoundTripsExactly) {
  Parameters p = pour();
  p.apply_cli({"--friction", "0.1", "--contact.kn", "0.3333333333333333", "--speeds",
               "5e-324,1e-300,2e8,0.1,1,12345.678901234567", "--output",
               "a \"quoted\": path\\ with # hash\nand a newline, é", "--label", "true", "--quiet", "--grains",
               "123456789"});
  const std::string dumped = p.to_yaml();
  // Every key, in spec order, the unset one as null.
  std::size_t at = 0;
  for (const auto& s : p.specs()) {
    const auto found = dumped.find("\n" + s.key + ": ", at == 0 ? 0 : at - 1);
    ASSERT_TRUE(dumped.rfind(s.key + ": ", 0) == 0 || found != std::string::npos)
        << s.key << " missing or out of order in:\n"
        << dumped;
    at = dumped.find(s.key + ": ", at) + 1;
  }
  EXPECT_NE(dumped.find("dt: ~\n"), std::string::npos) << dumped;
  // Floats look like floats also to YAML 1.1 readers (PyYAML in the workflow).
  EXPECT_NE(dumped.find("contact.kn: 0.3333333333333333\n"), std::string::npos) << dumped;
  EXPECT_NE(dumped.find("2.0e+08"), std::string::npos) << dumped;

  TempFile f(dumped, "roundtrip");
  Parameters q = pour();
  q.load_yaml(f.path());
  EXPECT_EQ(q.to_yaml(), dumped);
  EXPECT_TRUE(same_bits(q.number("friction"), p.number("friction")));
  EXPECT_TRUE(same_bits(q.number("contact.kn"), p.number("contact.kn")));
  EXPECT_TRUE(same_bits(q.number("poisson"), p.number("poisson")));
  const auto a = p.numbers("speeds"), b = q.numbers("speeds");
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) EXPECT_TRUE(same_bits(a[i], b[i])) << i;
  EXPECT_EQ(q.text("output"), p.text("output"));
  EXPECT_EQ(q.text("label"), "true");
  EXPECT_TRUE(q.flag("quiet"));
  EXPECT_EQ(q.integer("grains"), 123456789);
  EXPECT_FALSE(q.is_set("dt"));
}

TEST(Parameters, HelpTextListsEveryKeyWithUnitAndDefault) {
  const Parameters p = pour();
  const std::string help = p.help_text();
  for (const auto& s : p.specs()) {
    EXPECT_NE(help.find(s.key), std::string::npos) << s.key << "\n" << help;
    if (!s.unit.empty()) {
      EXPECT_NE(help.find(s.unit), std::string::npos) << s.unit;
    }
    if (!s.default_value.empty()) {
      EXPECT_NE(help.find(s.default_value), std::string::npos) << s.default_value;
    }
    EXPECT_NE(help.find(s.help), std::string::npos) << s.help;
  }
  EXPECT_NE(help.find("required"), std::string::npos);
  EXPECT_NE(help.find("(-1, 0.5)"), std::string::npos);
  EXPECT_NE(help.find("> 0"), std::string::npos);
}

TEST(Parameters, ToYamlRoundTripsRandomDoublesAndAwkwardText) {
  // Random bit patterns cover subnormals, huge and tiny exponents and 17-digit mantissas.
  std::mt19937_64 rng(12345);
  std::vector<double> values;
  while (values.size() < 2000) {
    const std::uint64_t bits = rng();
    double v;
    std::memcpy(&v, &bits, sizeof v);
    if (std::isfinite(v)) values.push_back(v);
  }
  for (const std::string& text :
       {std::string(""), std::string("~"), std::string("null"), std::string("- item"), std::string("[1, 2]"),
        std::string("  padded  "), std::string("'single'")}) {
    Parameters p = pour();
    p.apply_cli({"--label", text});
    TempFile f(p.to_yaml(), "text");
    Parameters q = pour();
    q.load_yaml(f.path());
    EXPECT_EQ(q.text("label"), text) << p.to_yaml();
  }
  // Set the list through YAML so that every double is given exactly.
  std::string yaml = "speeds: [";
  for (std::size_t i = 0; i < values.size(); ++i) {
    char buf[40];
    std::snprintf(buf, sizeof buf, "%.17g", values[i]);
    yaml += (i ? ", " : "") + std::string(buf);
  }
  TempFile in(yaml + "]\n", "random");
  Parameters p = pour();
  p.load_yaml(in.path());
  TempFile out(p.to_yaml(), "random_out");
  Parameters q = pour();
  q.load_yaml(out.path());
  const auto b = q.numbers("speeds");
  ASSERT_EQ(b.size(), values.size());
  for (std::size_t i = 0; i < values.size(); ++i)
    ASSERT_TRUE(same_bits(values[i], b[i])) << values[i] << " came back as " << b[i];
}

TEST(Parameters, BuilderNamesEveryField) {
  const ParameterSpec s = Key::number("lx").unit("d").default_value("20").above(4).below(100).help("box");
  EXPECT_EQ(s.key, "lx");
  EXPECT_EQ(s.type, Type::Number);
  EXPECT_EQ(s.unit, "d");
  EXPECT_EQ(s.default_value, "20");
  EXPECT_EQ(s.min, 4);
  EXPECT_TRUE(s.min_exclusive);
  EXPECT_EQ(s.max, 100);
  EXPECT_TRUE(s.max_exclusive);
  EXPECT_EQ(s.help, "box");
  EXPECT_FALSE(s.required);
  const ParameterSpec t = Key(s).at_least(1).at_most(2).default_value("");
  EXPECT_FALSE(t.min_exclusive);
  EXPECT_FALSE(t.max_exclusive);
  EXPECT_EQ(t.min, 1);
  EXPECT_EQ(t.unit, "d");  // kept from the row it started from
  EXPECT_TRUE(ParameterSpec(Key::text("output").required()).required);
  EXPECT_EQ(ParameterSpec(Key::numbers("v")).type, Type::NumberList);
  EXPECT_EQ(range_text(s), "(4, 100)");
  EXPECT_EQ(range_text(t), "[1, 2]");
}

TEST(Parameters, SchemaJsonStatesTypesRangesAndDefaults) {
  const std::string json = pour().schema_json();
  for (const std::string part :
       {"\"required\": [\"output\"]",
        "\"grains\": {\"type\": \"integer\", \"minimum\": 1, \"default\": 20000",
        "\"poisson\": {\"type\": \"number\", \"exclusiveMinimum\": -1, \"exclusiveMaximum\": 0.5, "
        "\"default\": 0.3",
        "\"speeds\": {\"type\": \"array\", \"items\": {\"type\": \"number\", \"exclusiveMinimum\": 0}, "
        "\"default\": [0.1, 1, 10]",
        "\"quiet\": {\"type\": \"boolean\", \"default\": false",
        "\"label\": {\"type\": \"string\", \"default\": \"bed\"",
        "\"dt\": {\"type\": \"number\", \"exclusiveMinimum\": 0, \"description\": \"time step [√(d/g)]\"}"})
    EXPECT_NE(json.find(part), std::string::npos) << "'" << part << "' missing from:\n" << json;
}

// Library entry points check a struct against the same rows, with the same messages.
TEST(Parameters, CheckRangesUsesTheRows) {
  const auto specs = pour_specs();
  EXPECT_NO_THROW(check_ranges(specs, {{"grains", 5}, {"poisson", 0.2}}, "test settings"));
  expect_error(
      [&] {
        check_ranges(specs, {{"grains", 0}}, "test settings");
      },
      {"'grains' = 0 is out of range: it must be >= 1", "from test settings"});
  expect_error(
      [&] {
        check_ranges(specs, {{"poisson", 0.5}, {"friction", NAN}}, "test settings");
      },
      {"2 problems in the test settings", "'poisson'", "(-1, 0.5)", "'friction' = nan", "finite"});
  EXPECT_THROW(check_ranges(specs, {{"no_such_key", 1}}, "x"), std::logic_error);
}
