// Parameters::load_yaml: a YAML parameter file, checked completely before anything is assigned.
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <optional>
#include <sstream>
#include <utility>

#include "core/error.hpp"
#include "core/parameters.hpp"

namespace granudrag {

using Type = ParameterSpec::Type;
using namespace detail;

namespace {

std::string yaml_scalar_text(const YAML::Node& node) {
  if (node.IsSequence()) {
    std::string s = "[";
    for (std::size_t i = 0; i < node.size(); ++i)
      s += (i ? ", " : "") + (node[i].IsScalar() ? node[i].Scalar() : std::string("..."));
    return s + "]";
  }
  return node.Scalar();
}

int line_of(const YAML::Node& node) { return node.Mark().line + 1; }

struct YamlEntry {
  std::string key;
  YAML::Node key_node, value;
};

}  // namespace

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
  // yaml-cpp 0.7 allocates without end on a document whose first token is ',' (found by
  // tests/cpp/test_fuzz_readers.cpp): refuse that before parsing. A document starts at the top,
  // after a '---' or '...' line; blank, comment and directive lines do not count.
  {
    std::istringstream lines(content.str());
    std::string line;
    bool at_start = true;
    int number = 0;
    while (std::getline(lines, line)) {
      ++number;
      const std::string t = trim(line);
      if (t.rfind("---", 0) == 0 || t.rfind("...", 0) == 0) {
        at_start = true;
        continue;
      }
      if (t.empty() || t[0] == '#' || t[0] == '%') continue;
      if (at_start && t[0] == ',')
        throw Error("YAML syntax error in the " + file + ", line " + std::to_string(number) +
                    ": a line cannot start with ',' (each line is 'key: value')");
      at_start = false;
    }
  }
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

}  // namespace granudrag
