#pragma once
// The parameters of a subcommand (`granudrag pour`, `granudrag pull`): declared once as a list
// of specs, read from a YAML file and/or `--key value` options, checked, and dumped back as YAML
// so that a run file records exactly what produced it.
//
// Precedence: command line > YAML file > default, whatever the order of the calls or of the
// arguments (a later YAML file overrides an earlier one). Type errors are raised when a value is
// read; range errors and missing required keys by validate(), all at once.
//
// Files: parameters.cpp (values, validation, YAML dump), parameters_yaml.cpp (reading YAML),
// parameters_cli.cpp (reading the command line), parameters_help.cpp (--help, --schema).
#include <string>
#include <vector>

#include "core/parameter_spec.hpp"
#include "core/parameter_values.hpp"

namespace granudrag {

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
  // A JSON Schema (draft-07) object of the keys: type, range, default, description with unit.
  std::string schema_json() const;

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
