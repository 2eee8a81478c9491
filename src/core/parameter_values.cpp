#include "core/parameter_values.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>

#include "core/error.hpp"

namespace granudrag::detail {

using Type = ParameterSpec::Type;

namespace {

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

// Integers may be written as 20000, 2e4 or 20000.0: "grains: 1e5" is natural in a study file.
std::optional<long> parse_long(const std::string& text) {
  const std::string t = trim(text);
  if (t.empty()) return std::nullopt;
  char* end = nullptr;
  errno = 0;
  const long v = std::strtol(t.c_str(), &end, 10);
  if (end == t.c_str() + t.size()) {
    if (errno == ERANGE) return std::nullopt;
    return v;
  }
  const auto d = parse_double(t);
  // Beyond 2^53 a double no longer says which integer was meant.
  if (!d || std::floor(*d) != *d || std::fabs(*d) > 9007199254740992.0) return std::nullopt;
  return static_cast<long>(*d);
}

std::optional<bool> parse_bool(const std::string& text) {
  const std::string t = lower(trim(text));
  if (t == "true" || t == "yes" || t == "on") return true;
  if (t == "false" || t == "no" || t == "off") return false;
  return std::nullopt;
}

// "1,2,3", "[1, 2, 3]", "5" or "" (the empty list).
std::optional<std::vector<double>> parse_list(const std::string& text) {
  std::string t = trim(text);
  if (t.size() >= 2 && t.front() == '[' && t.back() == ']') t = trim(t.substr(1, t.size() - 2));
  std::vector<double> out;
  if (t.empty()) return out;
  std::stringstream ss(t);
  std::string item;
  while (std::getline(ss, item, ',')) {
    const auto v = parse_double(item);
    if (!v) return std::nullopt;
    out.push_back(*v);
  }
  if (t.back() == ',') return std::nullopt;  // getline drops a trailing empty item
  return out;
}

bool bounded_below(const ParameterSpec& s) { return s.min != -ParameterSpec::unbounded; }
bool bounded_above(const ParameterSpec& s) { return s.max != ParameterSpec::unbounded; }

std::string with_unit(const std::string& text, const ParameterSpec& s) {
  return s.unit.empty() ? text : text + " " + s.unit;
}

// Optimal string alignment distance: Levenshtein plus adjacent transpositions ("friciton").
std::size_t edit_distance(const std::string& a, const std::string& b) {
  const std::size_t n = a.size(), m = b.size();
  std::vector<std::vector<std::size_t>> d(n + 1, std::vector<std::size_t>(m + 1));
  for (std::size_t i = 0; i <= n; ++i) d[i][0] = i;
  for (std::size_t j = 0; j <= m; ++j) d[0][j] = j;
  for (std::size_t i = 1; i <= n; ++i)
    for (std::size_t j = 1; j <= m; ++j) {
      const std::size_t cost = a[i - 1] == b[j - 1] ? 0 : 1;
      d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + cost});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1])
        d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
    }
  return d[n][m];
}

// Case and '-' versus '_' are the commonest slips between a YAML key and a command-line option.
std::string normalized(const std::string& key) {
  std::string s = lower(key);
  std::replace(s.begin(), s.end(), '-', '_');
  return s;
}

}  // namespace

std::string trim(const std::string& s) {
  const auto first = s.find_first_not_of(" \t\r\n");
  if (first == std::string::npos) return "";
  const auto last = s.find_last_not_of(" \t\r\n");
  return s.substr(first, last - first + 1);
}

const char* type_name(Type t) {
  switch (t) {
    case Type::Number:
      return "number";
    case Type::Integer:
      return "integer";
    case Type::Text:
      return "text";
    case Type::Flag:
      return "flag";
    case Type::NumberList:
      return "list";
  }
  return "?";
}

const char* accessor_name(Type t) {
  switch (t) {
    case Type::Number:
      return "number()";
    case Type::Integer:
      return "integer()";
    case Type::Text:
      return "text()";
    case Type::Flag:
      return "flag()";
    case Type::NumberList:
      return "numbers()";
  }
  return "?";
}

// The end of "'key' must be ..., got '...'".
const char* expectation(Type t) {
  switch (t) {
    case Type::Number:
      return "a number";
    case Type::Integer:
      return "an integer";
    case Type::Text:
      return "text";
    case Type::Flag:
      return "true or false";
    case Type::NumberList:
      return "a list of numbers (a YAML sequence [1, 2.5] or comma-separated 1,2.5)";
  }
  return "?";
}

// Shortest decimal form that reads back as the same double; 10 and 12345 without an exponent
// (%g would print the shortest "1e+01"), 2e+08 and 1e-05 with one.
std::string shortest(double v) {
  const int exponent = v == 0 ? 0 : static_cast<int>(std::floor(std::log10(std::fabs(v))));
  const int min_digits = exponent >= 0 && exponent < 6 ? exponent + 1 : 1;
  char buf[40];
  for (int digits = min_digits; digits <= 17; ++digits) {
    std::snprintf(buf, sizeof buf, "%.*g", digits, v);
    if (std::strtod(buf, nullptr) == v) break;
  }
  return buf;
}

// As shortest(), but always a float literal that YAML 1.1 readers (PyYAML, which the workflow
// uses) also take for a float: "2e+08" and "1" would come back as a string and an int there.
std::string yaml_number(double v) {
  std::string s = shortest(v);
  if (s.find('.') != std::string::npos) return s;
  const auto e = s.find('e');
  if (e == std::string::npos) return s + ".0";
  return s.insert(e, ".0");
}

std::optional<double> parse_double(const std::string& text) {
  const std::string t = trim(text);
  // strtod also takes hexadecimal, "inf" and "nan"; none belongs in a parameter file.
  if (t.empty() || t.find_first_of("xX") != std::string::npos) return std::nullopt;
  char* end = nullptr;
  const double v = std::strtod(t.c_str(), &end);
  if (end != t.c_str() + t.size() || !std::isfinite(v)) return std::nullopt;
  return v;
}

bool numeric(Type t) { return t == Type::Number || t == Type::Integer || t == Type::NumberList; }

// Parses `text` as a value of the spec's type; `source` says where it was written.
ParameterValue parse_value(const ParameterSpec& spec, const std::string& text, const std::string& source,
                           int level) {
  ParameterValue v;
  v.set = true;
  v.level = level;
  v.raw = text;
  v.source = source;
  bool ok = true;
  switch (spec.type) {
    case Type::Number: {
      const auto d = parse_double(text);
      if ((ok = d.has_value())) v.number = *d;
      break;
    }
    case Type::Integer: {
      const auto n = parse_long(text);
      if ((ok = n.has_value())) v.integer = *n;
      break;
    }
    case Type::Text:
      v.text = text;
      break;
    case Type::Flag: {
      const auto b = parse_bool(text);
      if ((ok = b.has_value())) v.flag = *b;
      break;
    }
    case Type::NumberList: {
      const auto l = parse_list(text);
      if ((ok = l.has_value())) v.list = *l;
      break;
    }
  }
  if (!ok)
    throw Error("'" + spec.key + "' must be " + expectation(spec.type) + ", got '" + text + "' (in " +
                source + ")");
  return v;
}

// "" when the value is within the spec's range, else the complete message.
std::string range_problem(const ParameterSpec& s, const ParameterValue& v) {
  if (!v.set || !numeric(s.type)) return "";
  std::string rule = range_text(s);
  if (bounded_below(s) && bounded_above(s)) rule = "in " + rule;
  const std::string context = " (" + (s.help.empty() ? "" : s.help + "; ") + "from " + v.source + ")";
  if (s.type == Type::NumberList) {
    for (std::size_t i = 0; i < v.list.size(); ++i)
      if (!in_range(s, v.list[i]))
        return "'" + s.key + "' = " + v.raw + " is out of range: every item must be " + with_unit(rule, s) +
               ", and item " + std::to_string(i + 1) + " is " + shortest(v.list[i]) + context;
    return "";
  }
  const double x = s.type == Type::Integer ? static_cast<double>(v.integer) : v.number;
  if (in_range(s, x)) return "";
  return "'" + s.key + "' = " + with_unit(trim(v.raw), s) + " is out of range: it must be " +
         with_unit(rule, s) + context;
}

// "; did you mean 'friction'?" for the nearest declared keys, or "" when none is near.
std::string suggestion(const std::string& wrong, const std::vector<ParameterSpec>& specs,
                       const std::string& prefix) {
  const std::string w = normalized(wrong);
  const std::size_t threshold = std::max<std::size_t>(1, std::min<std::size_t>(3, w.size() / 3));
  std::vector<std::string> near;
  std::size_t best = threshold + 1;
  for (const auto& s : specs) {
    const std::size_t d = edit_distance(w, normalized(s.key));
    if (d < best) {
      best = d;
      near.clear();
    }
    if (d == best) near.push_back(s.key);
  }
  // A fragment of a longer key ("diameter" for "intruder_diameter").
  if (near.empty() && w.size() >= 3)
    for (const auto& s : specs)
      if (normalized(s.key).find(w) != std::string::npos && near.size() < 3) near.push_back(s.key);
  if (near.empty()) return "";
  std::string out = "; did you mean ";
  for (std::size_t i = 0; i < near.size(); ++i) {
    if (i) out += i + 1 == near.size() ? " or " : ", ";
    out += "'" + prefix + near[i] + "'";
  }
  return out + "?";
}

bool valid_key(const std::string& key) {
  if (key.empty() || !std::isalpha(static_cast<unsigned char>(key[0])) || key.back() == '.' ||
      key.find("..") != std::string::npos)
    return false;
  return std::all_of(key.begin(), key.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.';
  });
}

}  // namespace granudrag::detail
