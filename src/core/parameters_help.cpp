// Parameters::help_text and Parameters::schema_json: the table behind --help and --schema.
#include <algorithm>
#include <array>
#include <cstdio>

#include "core/parameters.hpp"

namespace granudrag {

using Type = ParameterSpec::Type;
using namespace detail;

namespace {

// Columns of a UTF-8 string (units such as "√(d/g)" are several bytes per character).
std::size_t display_width(const std::string& s) {
  return static_cast<std::size_t>(std::count_if(
      s.begin(), s.end(), [](char c) { return (static_cast<unsigned char>(c) & 0xC0) != 0x80; }));
}

}  // namespace

std::string Parameters::help_text() const {
  std::vector<std::array<std::string, 6>> rows;
  rows.push_back({"key", "type", "unit", "default", "range", "meaning"});
  for (std::size_t i = 0; i < specs_.size(); ++i) {
    const ParameterSpec& s = specs_[i];
    std::string def = s.required ? "required" : s.default_value.empty() ? "none" : s.default_value;
    if (s.type == Type::Flag && s.default_value.empty()) def = "false";
    rows.push_back({s.key, type_name(s.type), s.unit.empty() ? "-" : s.unit, def,
                    numeric(s.type) ? range_text(s) : "-", s.help});
  }
  std::array<std::size_t, 5> width{};
  for (const auto& r : rows)
    for (std::size_t c = 0; c < width.size(); ++c) width[c] = std::max(width[c], display_width(r[c]));
  std::string out =
      "Parameters: --key value on the command line, or 'key: value' lines in a YAML file given\n"
      "with --config FILE; the command line wins. Lists: 1,2,3 or [1, 2, 3]. A flag alone\n"
      "(--key) means true.\n\n";
  for (const auto& r : rows) {
    std::string line = " ";
    for (std::size_t c = 0; c < width.size(); ++c)
      line += " " + r[c] + std::string(width[c] - display_width(r[c]) + 1, ' ');
    line += " " + r[5];
    out += line.substr(0, line.find_last_not_of(' ') + 1) + "\n";
  }
  return out;
}

namespace {

std::string json_string(const std::string& s) {
  std::string out = "\"";
  for (const char c : s) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (static_cast<unsigned char>(c) < 0x20) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\u%04x", static_cast<unsigned>(static_cast<unsigned char>(c)));
      out += buf;
    } else {
      out += c;
    }
  }
  return out + "\"";
}

// A number as JSON: integers of a double without a fraction ("20", not "20.0"; "9e+18" is fine).
std::string json_number(double v) { return shortest(v); }

const char* json_type(Type t) {
  switch (t) {
    case Type::Number:
      return "number";
    case Type::Integer:
      return "integer";
    case Type::Text:
      return "string";
    case Type::Flag:
      return "boolean";
    case Type::NumberList:
      return "array";
  }
  return "?";
}

// "minimum": 0, "exclusiveMaximum": 0.5, ... for the spec's bounds.
std::string json_bounds(const ParameterSpec& s) {
  std::string out;
  if (s.min != -ParameterSpec::unbounded)
    out += std::string(", \"") + (s.min_exclusive ? "exclusiveMinimum" : "minimum") +
           "\": " + json_number(s.min);
  if (s.max != ParameterSpec::unbounded)
    out += std::string(", \"") + (s.max_exclusive ? "exclusiveMaximum" : "maximum") +
           "\": " + json_number(s.max);
  return out;
}

std::string json_value(const ParameterValue& v, Type t) {
  switch (t) {
    case Type::Number:
      return json_number(v.number);
    case Type::Integer:
      return std::to_string(v.integer);
    case Type::Text:
      return json_string(v.text);
    case Type::Flag:
      return v.flag ? "true" : "false";
    case Type::NumberList: {
      std::string out = "[";
      for (std::size_t i = 0; i < v.list.size(); ++i) out += (i ? ", " : "") + json_number(v.list[i]);
      return out + "]";
    }
  }
  return "null";
}

}  // namespace

std::string Parameters::schema_json() const {
  std::string properties, required;
  for (std::size_t i = 0; i < specs_.size(); ++i) {
    const ParameterSpec& s = specs_[i];
    std::string p = std::string("{\"type\": \"") + json_type(s.type) + "\"";
    if (s.type == Type::NumberList)
      p += ", \"items\": {\"type\": \"number\"" + json_bounds(s) + "}";
    else if (numeric(s.type))
      p += json_bounds(s);
    // The declared default (a flag without one is off); values_ may hold a later setting.
    if (!s.default_value.empty() || s.type == Type::Flag) {
      const std::string text = s.default_value.empty() ? "false" : s.default_value;
      p += ", \"default\": " + json_value(parse_value(s, text, "the default", kDefaultLevel), s.type);
    }
    const std::string description = s.help + (s.unit.empty() ? "" : " [" + s.unit + "]");
    p += ", \"description\": " + json_string(description) + "}";
    properties += std::string(i ? ",\n" : "") + "    " + json_string(s.key) + ": " + p;
    if (s.required) required += std::string(required.empty() ? "" : ", ") + json_string(s.key);
  }
  return "{\n  \"$schema\": \"http://json-schema.org/draft-07/schema#\",\n  \"title\": " +
         json_string("granudrag " + command_) +
         ",\n  \"type\": \"object\",\n  \"additionalProperties\": false,\n  \"required\": [" + required +
         "],\n  \"properties\": {\n" + properties + "\n  }\n}\n";
}

}  // namespace granudrag
