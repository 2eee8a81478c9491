#pragma once
// Internals shared by the files of Parameters (parameters*.cpp, parameter_spec.cpp): one key's
// parsed value, parsing and formatting of values, and the texts of messages. Not an API.
#include <optional>
#include <string>
#include <vector>

#include "core/parameter_spec.hpp"

namespace granudrag::detail {

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

constexpr int kDefaultLevel = 0, kYamlLevel = 1, kCliLevel = 2;

std::string trim(const std::string& s);
const char* type_name(ParameterSpec::Type t);      // "number", "integer", ...
const char* accessor_name(ParameterSpec::Type t);  // "number()", ...
const char* expectation(ParameterSpec::Type t);    // the end of "'key' must be ..., got '...'"
bool numeric(ParameterSpec::Type t);

// Shortest decimal form that reads back as the same double; 10 and 12345 without an exponent.
std::string shortest(double v);
// As shortest(), but always a float literal to YAML 1.1 readers (PyYAML): "2.0e+08", "1.0".
std::string yaml_number(double v);
std::optional<double> parse_double(const std::string& text);

// Parses `text` as a value of the spec's type; `source` says where it was written. Throws
// granudrag::Error naming the key for a value of the wrong type.
ParameterValue parse_value(const ParameterSpec& spec, const std::string& text, const std::string& source,
                           int level);

// "" when the value is within the spec's range, else the complete message.
std::string range_problem(const ParameterSpec& spec, const ParameterValue& value);

// "; did you mean 'friction'?" for the nearest declared keys, or "" when none is near.
std::string suggestion(const std::string& wrong, const std::vector<ParameterSpec>& specs,
                       const std::string& prefix);

bool valid_key(const std::string& key);

}  // namespace granudrag::detail
