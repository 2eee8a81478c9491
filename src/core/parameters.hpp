#pragma once
// The parameters of a subcommand (`granudrag pour`, `granudrag pull`): declared once as a list
// of specs, read from a YAML file and/or `--key value` options, checked, and dumped back as YAML
// so that a run file records exactly what produced it.
//
// Precedence: command line > YAML file > default, whatever the order of the calls or of the
// arguments (a later YAML file overrides an earlier one). Type errors are raised when a value is
// read; range errors and missing required keys by validate(), all at once.
#include <limits>
#include <string>
#include <vector>

namespace granudrag {

struct ParameterSpec {
  enum class Type { Number, Integer, Text, Flag, NumberList };
  static constexpr double unbounded = std::numeric_limits<double>::infinity();

  std::string key{};  // letters, digits, '_', '-', '.'; must start with a letter
  Type type = Type::Number;
  std::string unit{};           // "" for dimensionless
  std::string default_value{};  // as it would be written on the command line; "" = none
  double min = -unbounded;      // inclusive unless min_exclusive; Number, Integer, NumberList items
  double max = unbounded;       // inclusive unless max_exclusive
  bool min_exclusive = false;
  std::string help{};
  bool required = false;       // no default allowed: the user must give it
  bool max_exclusive = false;  // last, so that positional initialisers above stay valid
};

namespace detail {
// One key's value, as parsed for its type.
struct ParameterValue {
  bool set = false;
  int level = 0;             // 0 default, 1 YAML, 2 command line: a lower level never overrides a higher
  double number = 0;         // Number
  long integer = 0;          // Integer
  std::string text;          // Text
  bool flag = false;         // Flag
  std::vector<double> list;  // NumberList
  std::string raw;           // as written, for messages
  std::string source;        // where it came from, for messages
};
}  // namespace detail

class Parameters {
 public:
  // Throws std::logic_error for a malformed spec list (duplicate or reserved key, a default that
  // does not parse or is out of range, a required key with a default): those are code bugs.
  Parameters(std::string command, std::vector<ParameterSpec> specs);

  // A flat mapping `key: value`; a nested mapping `group: {key: value}` is read as the dotted
  // key `group.key`. A null value (`key:` or `key: ~`) means "not given here". An empty file sets
  // nothing. Throws granudrag::Error naming the file (and line) for an unreadable file, a syntax
  // error, a top level that is not a mapping, an unknown key (with the closest known keys), a
  // key given twice, or a value of the wrong type.
  void load_yaml(const std::string& path);

  // `--key value`, `--key=value`, `--flag` (= true) or `--flag true|false`; `--config FILE`
  // (repeatable) loads YAML files first, in order, so the other options override them wherever
  // they stand. `--help` is not handled here. On any error nothing is changed.
  void apply_cli(const std::vector<std::string>& args);

  // Every required key present and every value within its range; one Error listing all problems.
  void validate() const;

  // Typed access. An undeclared key or the wrong accessor for its type is a std::logic_error; a
  // declared key that has no value (no default, not given) is a granudrag::Error.
  double number(const std::string& key) const;
  long integer(const std::string& key) const;
  std::string text(const std::string& key) const;
  bool flag(const std::string& key) const;
  std::vector<double> numbers(const std::string& key) const;
  bool is_set(const std::string& key) const;  // has a value, from the default or given

  // Every key in spec order, defaults included, unset keys as `~`; load_yaml() of it reproduces
  // every value bit for bit.
  std::string to_yaml() const;
  // A table: key, type, unit, default, range, help.
  std::string help_text() const;

  const std::string& command() const { return command_; }
  const std::vector<ParameterSpec>& specs() const { return specs_; }

 private:
  std::size_t index_of(const std::string& key) const;
  const detail::ParameterValue& value_of(const std::string& key, ParameterSpec::Type type) const;
  void assign(std::size_t index, detail::ParameterValue value);

  std::string command_;
  std::vector<ParameterSpec> specs_;
  std::vector<detail::ParameterValue> values_;
};

}  // namespace granudrag
