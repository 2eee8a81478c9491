#include "app/cli.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "core/error.hpp"

namespace granudrag {

Options::Options(const std::vector<std::string>& args, const std::vector<std::string>& allowed,
                 const std::string& command)
    : command_(command) {
  for (std::size_t k = 0; k < args.size(); ++k) {
    const std::string& a = args[k];
    if (a.rfind("--", 0) != 0)
      throw Error("unexpected argument '" + a + "' for '" + command +
                  "': options have the form --key value (see granudrag " + command + " --help)");
    const std::string key = a.substr(2);
    if (std::find(allowed.begin(), allowed.end(), key) == allowed.end()) {
      std::string list;
      for (const auto& k2 : allowed) list += " --" + k2;
      throw Error("unknown option '--" + key + "' for '" + command + "'; valid options:" + list);
    }
    if (k + 1 >= args.size()) throw Error("option '--" + key + "' needs a value");
    values_[key] = args[++k];
  }
}

std::string Options::text(const std::string& key, const std::string& fallback) const {
  auto it = values_.find(key);
  return it == values_.end() ? fallback : it->second;
}

double Options::number(const std::string& key, double fallback) const {
  auto it = values_.find(key);
  if (it == values_.end()) return fallback;
  std::size_t used = 0;
  double value = 0;
  try {
    value = std::stod(it->second, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != it->second.size() || !std::isfinite(value))
    throw Error("option '--" + key + "' of '" + command_ + "' must be a number (got '" + it->second + "')");
  return value;
}

long Options::integer(const std::string& key, long fallback, long min_value) const {
  auto it = values_.find(key);
  if (it == values_.end()) return fallback;
  std::size_t used = 0;
  long value = 0;
  try {
    value = std::stol(it->second, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != it->second.size())
    throw Error("option '--" + key + "' of '" + command_ + "' must be an integer (got '" + it->second + "')");
  if (value < min_value)
    throw Error("option '--" + key + "' of '" + command_ + "' must be >= " + std::to_string(min_value) +
                " (got " + it->second + ")");
  return value;
}

std::vector<int> Options::integer_list(const std::string& key, const std::vector<int>& fallback) const {
  auto it = values_.find(key);
  if (it == values_.end()) return fallback;
  std::vector<int> out;
  std::stringstream ss(it->second);
  std::string item;
  while (std::getline(ss, item, ',')) {
    std::size_t used = 0;
    int v = 0;
    try {
      v = std::stoi(item, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used != item.size() || v < 1)
      throw Error("option '--" + key + "' must be a comma-separated list of positive integers (got '" +
                  it->second + "')");
    out.push_back(v);
  }
  if (out.empty()) throw Error("option '--" + key + "' is empty");
  return out;
}

}  // namespace granudrag
