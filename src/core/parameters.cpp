#include "core/parameters.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "core/error.hpp"

namespace granudrag {

using Type = ParameterSpec::Type;
using detail::ParameterValue;

namespace {

constexpr int kDefaultLevel = 0, kYamlLevel = 1, kCliLevel = 2;

std::string trim(const std::string& s) {
  const auto first = s.find_first_not_of(" \t\r\n");
  if (first == std::string::npos) return "";
  const auto last = s.find_last_not_of(" \t\r\n");
  return s.substr(first, last - first + 1);
}

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
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

std::string join(const std::vector<double>& list, const char* separator, std::string (*format)(double)) {
  std::string s;
  for (std::size_t i = 0; i < list.size(); ++i) s += (i ? separator : "") + format(list[i]);
  return s;
}

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

bool bounded_below(const ParameterSpec& s) { return s.min != -ParameterSpec::unbounded; }
bool bounded_above(const ParameterSpec& s) { return s.max != ParameterSpec::unbounded; }
bool numeric(Type t) { return t == Type::Number || t == Type::Integer || t == Type::NumberList; }

// "[0, 1)", ">= 0", "< 0.5" or "any".
std::string range_text(const ParameterSpec& s) {
  const bool lo = bounded_below(s), hi = bounded_above(s);
  if (lo && hi)
    return std::string(s.min_exclusive ? "(" : "[") + shortest(s.min) + ", " + shortest(s.max) +
           (s.max_exclusive ? ")" : "]");
  if (lo) return std::string(s.min_exclusive ? "> " : ">= ") + shortest(s.min);
  if (hi) return std::string(s.max_exclusive ? "< " : "<= ") + shortest(s.max);
  return "any";
}

bool in_range(const ParameterSpec& s, double x) {
  const bool lo_ok = s.min_exclusive ? x > s.min : x >= s.min;
  const bool hi_ok = s.max_exclusive ? x < s.max : x <= s.max;
  return lo_ok && hi_ok;
}

std::string with_unit(const std::string& text, const ParameterSpec& s) {
  return s.unit.empty() ? text : text + " " + s.unit;
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

std::string yaml_scalar_text(const YAML::Node& node) {
  if (node.IsSequence()) {
    std::string s = "[";
    for (std::size_t i = 0; i < node.size(); ++i)
      s += (i ? ", " : "") + (node[i].IsScalar() ? node[i].Scalar() : std::string("..."));
    return s + "]";
  }
  return node.Scalar();
}

// Columns of a UTF-8 string (units such as "√(d/g)" are several bytes per character).
std::size_t display_width(const std::string& s) {
  return static_cast<std::size_t>(std::count_if(
      s.begin(), s.end(), [](char c) { return (static_cast<unsigned char>(c) & 0xC0) != 0x80; }));
}

int line_of(const YAML::Node& node) { return node.Mark().line + 1; }

struct YamlEntry {
  std::string key;
  YAML::Node key_node, value;
};

}  // namespace

Parameters::Parameters(std::string command, std::vector<ParameterSpec> specs)
    : command_(std::move(command)), specs_(std::move(specs)) {
  values_.resize(specs_.size());
  for (std::size_t i = 0; i < specs_.size(); ++i) {
    const ParameterSpec& s = specs_[i];
    const std::string where = "parameter spec '" + s.key + "' of " + command_ + ": ";
    if (!valid_key(s.key))
      throw std::logic_error(where + "keys are letters, digits, '_', '-' and '.', from a letter");
    if (s.key == "config" || s.key == "help")
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

void Parameters::load_yaml(const std::string& path) {
  const std::string file = "parameter file '" + path + "'";
  std::error_code ec;
  if (!std::filesystem::exists(path, ec))
    throw Error("cannot read the " + file + " for granudrag " + command_ +
                ": it does not exist (check the path; relative paths start in the current "
                "directory)");
  if (std::filesystem::is_directory(path, ec))
    throw Error("cannot read the " + file + ": it is a directory, not a YAML file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error("cannot read the " + file + ": " + std::strerror(errno) + " (check its permissions)");
  std::ostringstream content;
  content << in.rdbuf();
  if (in.bad()) throw Error("cannot read the " + file + ": read error");

  std::vector<YAML::Node> documents;
  try {
    documents = YAML::LoadAll(content.str());
  } catch (const YAML::Exception& e) {
    std::string at;
    if (e.mark.line >= 0)
      at = ", line " + std::to_string(e.mark.line + 1) + ", column " + std::to_string(e.mark.column + 1);
    throw Error("YAML syntax error in the " + file + at + ": " + e.msg +
                " (each line is 'key: value'; quote values that contain ': ' or ' #')");
  }
  if (documents.size() > 1)
    throw Error("the " + file + " holds " + std::to_string(documents.size()) +
                " YAML documents (separated by '---'); put every parameter in one mapping");
  if (documents.empty() || documents[0].IsNull()) return;  // empty or only comments
  const YAML::Node& root = documents[0];
  if (!root.IsMap())
    throw Error("the " + file + " must be a mapping of 'key: value' lines, but its top level is " +
                (root.IsSequence() ? "a list" : "the single value '" + root.Scalar() + "'") + " (line " +
                std::to_string(line_of(root)) + ")");

  // Flatten nested mappings into dotted keys, then check and parse everything before assigning
  // anything, so that a bad file leaves the parameters as they were.
  std::vector<YamlEntry> entries;
  const auto is_group = [this](const std::string& prefix) {
    return std::any_of(specs_.begin(), specs_.end(),
                       [&](const ParameterSpec& s) { return s.key.rfind(prefix + ".", 0) == 0; });
  };
  std::function<void(const YAML::Node&, const std::string&)> walk;
  walk = [&](const YAML::Node& map, const std::string& prefix) {
    for (const auto& kv : map) {
      if (!kv.first.IsScalar())
        throw Error("the " + file + ", line " + std::to_string(line_of(kv.first)) +
                    ": keys must be plain names, not lists or mappings");
      const std::string key = prefix + kv.first.Scalar();
      if (kv.second.IsMap() && is_group(key))
        walk(kv.second, key + ".");
      else
        entries.push_back({key, kv.first, kv.second});
    }
  };
  walk(root, "");

  std::map<std::string, int> seen;  // key -> line
  std::vector<std::pair<std::size_t, ParameterValue>> pending;
  for (const auto& e : entries) {
    const int line = line_of(e.key_node);
    const std::string source = path + ", line " + std::to_string(line);
    const auto it =
        std::find_if(specs_.begin(), specs_.end(), [&](const ParameterSpec& s) { return s.key == e.key; });
    if (it == specs_.end())
      throw Error("unknown key '" + e.key + "' in " + path + " (line " + std::to_string(line) + ")" +
                  suggestion(e.key, specs_, "") + " (granudrag " + command_ + " --help lists every key)");
    if (!seen.emplace(e.key, line).second)
      throw Error("'" + e.key + "' is given twice in " + path + " (lines " + std::to_string(seen[e.key]) +
                  " and " + std::to_string(line) + "); keep one");
    const ParameterSpec& spec = *it;
    const std::size_t index = static_cast<std::size_t>(it - specs_.begin());
    if (e.value.IsNull()) continue;  // `key:` or `key: ~`: not given here
    if (e.value.IsMap())
      throw Error("'" + e.key + "' must be " + expectation(spec.type) + ", got a mapping (in " + source +
                  ")");
    if (e.value.IsSequence()) {
      if (spec.type != Type::NumberList)
        throw Error("'" + e.key + "' must be " + expectation(spec.type) + ", got the list '" +
                    yaml_scalar_text(e.value) + "' (in " + source + ")");
      ParameterValue v;
      v.set = true;
      v.level = kYamlLevel;
      v.raw = yaml_scalar_text(e.value);
      v.source = source;
      for (const auto& item : e.value) {
        const auto d = item.IsScalar() ? parse_double(item.Scalar()) : std::nullopt;
        if (!d)
          throw Error("'" + e.key + "' must be " + expectation(spec.type) + ", got '" + v.raw + "' (in " +
                      source + ")");
        v.list.push_back(*d);
      }
      pending.emplace_back(index, std::move(v));
      continue;
    }
    pending.emplace_back(index, parse_value(spec, e.value.Scalar(), source, kYamlLevel));
  }
  for (auto& [index, value] : pending) assign(index, std::move(value));
}

void Parameters::apply_cli(const std::vector<std::string>& args) {
  const std::string see_help = " (granudrag " + command_ + " --help lists every option)";
  std::vector<std::string> configs;
  std::vector<std::pair<std::size_t, ParameterValue>> pending;
  std::vector<bool> given(specs_.size(), false);
  for (std::size_t k = 0; k < args.size(); ++k) {
    const std::string& arg = args[k];
    if (arg.size() < 3 || arg.compare(0, 2, "--") != 0)
      throw Error("unexpected argument '" + arg + "' for granudrag " + command_ +
                  ": options have the form --key value" + see_help);
    std::string name = arg.substr(2);
    std::optional<std::string> inline_value;
    if (const auto eq = name.find('='); eq != std::string::npos) {
      inline_value = name.substr(eq + 1);
      name.resize(eq);
    }
    const bool next_is_value = k + 1 < args.size() && args[k + 1].compare(0, 2, "--") != 0;

    if (name == "config") {
      if (inline_value)
        configs.push_back(*inline_value);
      else if (next_is_value)
        configs.push_back(args[++k]);
      else
        throw Error("option '--config' needs the path of a YAML parameter file");
      continue;
    }
    const auto it =
        std::find_if(specs_.begin(), specs_.end(), [&](const ParameterSpec& s) { return s.key == name; });
    if (it == specs_.end())
      throw Error("unknown option '--" + name + "' for granudrag " + command_ +
                  suggestion(name, specs_, "--") + see_help);
    const std::size_t index = static_cast<std::size_t>(it - specs_.begin());
    if (given[index]) throw Error("option '--" + name + "' is given twice on the command line; keep one");
    given[index] = true;

    std::string text;
    if (inline_value)
      text = *inline_value;
    else if (next_is_value)  // a single '-' is a value: --mu -0.1
      text = args[++k];
    else if (it->type == Type::Flag)
      text = "true";
    else
      throw Error("option '--" + name + "' needs a value: " + expectation(it->type) +
                  (it->unit.empty() ? "" : " in " + it->unit) + see_help);
    pending.emplace_back(index, parse_value(*it, text, "--" + name + " on the command line", kCliLevel));
  }
  // Work on a copy: a bad file or value leaves *this untouched.
  Parameters staged = *this;
  for (const auto& path : configs) staged.load_yaml(path);
  for (auto& [index, value] : pending) staged.assign(index, std::move(value));
  *this = std::move(staged);
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

}  // namespace granudrag
