#pragma once
// One parameter of a command, declared once: its key, type, unit, default, range and meaning.
// The command line, the YAML reader, validation, --help and --schema all read this one row.
//
// Rows are written with named fields through the Key builder:
//
//   Key::number("lx").unit("d").default_value("20").at_least(4).help("box length along x")
//   Key::text("output").required().help("bed file to write (HDF5)")
//
// A row that is a field of a struct says so with .field(&PourSpec::lx) instead of stating a
// default: parameter_table.hpp.
#include <limits>
#include <string>
#include <utility>
#include <vector>

namespace granudrag {

template <class Spec>
struct BoundKey;

struct ParameterSpec {
  enum class Type { Number, Integer, Text, Flag, NumberList };
  static constexpr double unbounded = std::numeric_limits<double>::infinity();

  std::string key{};  // letters, digits, '_', '-', '.'; must start with a letter
  Type type = Type::Number;
  std::string unit{};           // "" for dimensionless
  std::string default_value{};  // as it would be written on the command line; "" = none
  double min = -unbounded;      // Number, Integer and NumberList items; inclusive unless min_exclusive
  double max = unbounded;       // inclusive unless max_exclusive
  bool min_exclusive = false;
  bool max_exclusive = false;
  std::string help{};
  bool required = false;  // no default allowed: the user must give it
};

// Builds a ParameterSpec field by field. Each call returns the builder, and the builder converts
// to the ParameterSpec it holds, so rows go straight into a std::vector<ParameterSpec>.
class Key {
 public:
  static Key number(std::string key) { return Key(std::move(key), ParameterSpec::Type::Number); }
  static Key integer(std::string key) { return Key(std::move(key), ParameterSpec::Type::Integer); }
  static Key text(std::string key) { return Key(std::move(key), ParameterSpec::Type::Text); }
  static Key flag(std::string key) { return Key(std::move(key), ParameterSpec::Type::Flag); }
  static Key numbers(std::string key) { return Key(std::move(key), ParameterSpec::Type::NumberList); }
  // Starts from an existing row, to change what differs (another default, another help text).
  explicit Key(ParameterSpec spec) : spec_(std::move(spec)) {}

  Key unit(std::string unit) && { return std::move(*this).set(&ParameterSpec::unit, std::move(unit)); }
  // As written on the command line: "20", "2e8", "0.1,1,10", "true".
  Key default_value(std::string text) && {
    return std::move(*this).set(&ParameterSpec::default_value, std::move(text));
  }
  Key help(std::string text) && { return std::move(*this).set(&ParameterSpec::help, std::move(text)); }
  Key required() && { return std::move(*this).set(&ParameterSpec::required, true); }
  Key at_least(double min) && { return std::move(*this).lower(min, false); }  // >= min
  Key above(double min) && { return std::move(*this).lower(min, true); }      // > min
  Key at_most(double max) && { return std::move(*this).upper(max, false); }   // <= max
  Key below(double max) && { return std::move(*this).upper(max, true); }      // < max

  // Binds the row to a field of Spec, or to a field of one of its members (&PullSpec::active,
  // &ActiveRegionSettings::radius); defined in parameter_table.hpp.
  template <class Spec, class T>
  BoundKey<Spec> field(T Spec::*member) &&;
  template <class Spec, class Group, class T>
  BoundKey<Spec> field(Group Spec::*group, T Group::*member) &&;

  operator ParameterSpec() && { return std::move(spec_); }  // NOLINT: implicit by design
  operator ParameterSpec() const& { return spec_; }         // NOLINT
  const ParameterSpec& spec() const { return spec_; }

 private:
  Key(std::string key, ParameterSpec::Type type) {
    spec_.key = std::move(key);
    spec_.type = type;
  }
  template <class T, class V>
  Key set(T ParameterSpec::*field, V&& value) && {
    spec_.*field = std::forward<V>(value);
    return std::move(*this);
  }
  Key lower(double min, bool exclusive) && {
    spec_.min = min;
    spec_.min_exclusive = exclusive;
    return std::move(*this);
  }
  Key upper(double max, bool exclusive) && {
    spec_.max = max;
    spec_.max_exclusive = exclusive;
    return std::move(*this);
  }
  ParameterSpec spec_;
};

// The row of `key` in `specs`; std::logic_error when there is none (a code bug).
const ParameterSpec& find_spec(const std::vector<ParameterSpec>& specs, const std::string& key);

// A number as a person writes it on the command line: the fewest digits that read back as `v`,
// in the shorter of plain and scientific notation, the exponent unpadded ("0.02", "20", "1e-7",
// "5e4", "2e8").
std::string number_text(double v);

// "[0, 1)", ">= 0", "< 0.5" or "any".
std::string range_text(const ParameterSpec& spec);
bool in_range(const ParameterSpec& spec, double value);

// For library entry points that take a struct rather than Parameters (PourSpec, PullSpec): checks
// each (key, value) against its row's range, with the messages Parameters::validate() gives, and
// throws one granudrag::Error listing every problem. `source` says where the values came from.
void check_ranges(const std::vector<ParameterSpec>& specs,
                  const std::vector<std::pair<std::string, double>>& values, const std::string& source);

}  // namespace granudrag
