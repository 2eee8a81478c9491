#include "core/parameters.hpp"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <stdexcept>
#include <utility>

#include "core/error.hpp"

namespace granudrag {

using Type = ParameterSpec::Type;
using namespace detail;

namespace {

std::string join(const std::vector<double>& list, const char* separator, std::string (*format)(double)) {
  std::string s;
  for (std::size_t i = 0; i < list.size(); ++i) s += (i ? separator : "") + format(list[i]);
  return s;
}

}  // namespace

Parameters::Parameters(std::string command, std::vector<ParameterSpec> specs)
    : command_(std::move(command)), specs_(std::move(specs)) {
  values_.resize(specs_.size());
  for (std::size_t i = 0; i < specs_.size(); ++i) {
    const ParameterSpec& s = specs_[i];
    const std::string where = "parameter spec '" + s.key + "' of " + command_ + ": ";
    if (!valid_key(s.key))
      throw std::logic_error(where + "keys are letters, digits, '_', '-' and '.', from a letter");
    if (s.key == "config" || s.key == "help" || s.key == "schema")
      throw std::logic_error(where + "'" + s.key + "' is reserved for the command line");
    for (std::size_t j = 0; j < i; ++j)
      if (specs_[j].key == s.key) throw std::logic_error(where + "declared twice");
    if (std::isnan(s.min) || std::isnan(s.max) || s.min > s.max) throw std::logic_error(where + "min > max");
    if (s.required && (!s.default_value.empty() || s.type == Type::Flag))
      throw std::logic_error(where + "a required key has no default (and a flag always has one)");
    // A flag is never unset: without a default it is off.
    const std::string text = s.type == Type::Flag && s.default_value.empty() ? "false" : s.default_value;
    if (text.empty()) continue;
    try {
      values_[i] = parse_value(s, text, "the default", kDefaultLevel);
    } catch (const Error& e) {
      throw std::logic_error(where + "bad default: " + e.what());
    }
    const std::string problem = range_problem(s, values_[i]);
    if (!problem.empty()) throw std::logic_error(where + "default out of range: " + problem);
  }
}

std::size_t Parameters::index_of(const std::string& key) const {
  for (std::size_t i = 0; i < specs_.size(); ++i)
    if (specs_[i].key == key) return i;
  throw std::logic_error("granudrag " + command_ + " has no parameter '" + key +
                         "': it is read but not declared in the spec list");
}

const ParameterValue& Parameters::value_of(const std::string& key, Type type) const {
  const std::size_t i = index_of(key);
  const ParameterSpec& s = specs_[i];
  if (s.type != type)
    throw std::logic_error("parameter '" + key + "' of " + command_ + " is a " + type_name(s.type) +
                           ": read it with " + accessor_name(s.type));
  if (!values_[i].set)
    throw Error("'" + key + "'" + (s.help.empty() ? "" : " (" + s.help + ")") +
                " has no value: give it in the YAML file (" + key + ": ...) or as --" + key + " ...");
  return values_[i];
}

void Parameters::assign(std::size_t index, ParameterValue value) {
  if (value.level >= values_[index].level) values_[index] = std::move(value);
}

void Parameters::validate() const {
  std::vector<std::string> problems;
  for (std::size_t i = 0; i < specs_.size(); ++i) {
    const ParameterSpec& s = specs_[i];
    if (!values_[i].set) {
      if (s.required)
        problems.push_back("'" + s.key + "'" + (s.help.empty() ? "" : " (" + s.help + ")") +
                           " is required but was not given: set it in the YAML file (" + s.key +
                           ": ...) or on the command line (--" + s.key + " ...)");
      continue;
    }
    std::string problem = range_problem(s, values_[i]);
    if (!problem.empty()) problems.push_back(std::move(problem));
  }
  if (problems.empty()) return;
  if (problems.size() == 1) throw Error(problems[0]);
  std::string msg =
      std::to_string(problems.size()) + " problems with the parameters of granudrag " + command_ + ":";
  for (const auto& p : problems) msg += "\n  - " + p;
  throw Error(msg);
}

double Parameters::number(const std::string& key) const { return value_of(key, Type::Number).number; }
long Parameters::integer(const std::string& key) const { return value_of(key, Type::Integer).integer; }
std::string Parameters::text(const std::string& key) const { return value_of(key, Type::Text).text; }
bool Parameters::flag(const std::string& key) const { return value_of(key, Type::Flag).flag; }
std::vector<double> Parameters::numbers(const std::string& key) const {
  return value_of(key, Type::NumberList).list;
}
bool Parameters::is_set(const std::string& key) const { return values_[index_of(key)].set; }

std::string Parameters::to_yaml() const {
  std::string out;
  for (std::size_t i = 0; i < specs_.size(); ++i) {
    const ParameterSpec& s = specs_[i];
    const ParameterValue& v = values_[i];
    out += s.key + ": ";
    if (!v.set) {
      out += "~\n";
      continue;
    }
    switch (s.type) {
      case Type::Number:
        out += yaml_number(v.number);
        break;
      case Type::Integer:
        out += std::to_string(v.integer);
        break;
      case Type::Flag:
        out += v.flag ? "true" : "false";
        break;
      case Type::NumberList:
        out += "[" + join(v.list, ", ", yaml_number) + "]";
        break;
      case Type::Text: {
        // Always quoted: "true", "1e5", "~" or "a: b" must come back as the same text.
        YAML::Emitter emitter;
        emitter << YAML::DoubleQuoted << v.text;
        out += emitter.c_str();
        break;
      }
    }
    out += "\n";
  }
  return out;
}
}  // namespace granudrag
