#include "core/parameter_spec.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <stdexcept>

#include "core/error.hpp"
#include "core/parameter_values.hpp"

namespace granudrag {

using detail::shortest;

const ParameterSpec& find_spec(const std::vector<ParameterSpec>& specs, const std::string& key) {
  for (const auto& s : specs)
    if (s.key == key) return s;
  throw std::logic_error("no parameter '" + key + "' is declared in this spec list");
}

namespace {

// "1e-07" -> "1e-7", "2e+08" -> "2e8".
std::string compact_exponent(const std::string& s) {
  const auto e = s.find('e');
  if (e == std::string::npos) return s;
  std::size_t digits = e + 1;
  const bool negative = digits < s.size() && s[digits] == '-';
  if (digits < s.size() && (s[digits] == '+' || s[digits] == '-')) ++digits;
  const std::size_t first = s.find_first_not_of('0', digits);
  return s.substr(0, e + 1) + (negative ? "-" : "") + (first == std::string::npos ? "0" : s.substr(first));
}

}  // namespace

std::string number_text(double v) {
  const std::string plain = compact_exponent(shortest(v));
  char buf[40];
  for (int digits = 0; digits <= 16; ++digits) {
    std::snprintf(buf, sizeof buf, "%.*e", digits, v);
    if (std::strtod(buf, nullptr) == v) break;
  }
  const std::string scientific = compact_exponent(buf);
  return scientific.size() < plain.size() ? scientific : plain;
}

std::string range_text(const ParameterSpec& s) {
  const bool lo = s.min != -ParameterSpec::unbounded, hi = s.max != ParameterSpec::unbounded;
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

void check_ranges(const std::vector<ParameterSpec>& specs,
                  const std::vector<std::pair<std::string, double>>& values, const std::string& source) {
  std::vector<std::string> problems;
  for (const auto& [key, x] : values) {
    const ParameterSpec& s = find_spec(specs, key);
    // NaN and infinities are never a valid setting, whatever the range.
    if (!std::isfinite(x)) {
      problems.push_back("'" + key + "' = " + shortest(x) + " is not a finite number (from " + source + ")");
      continue;
    }
    detail::ParameterValue v;
    v.set = true;
    v.source = source;
    v.raw = shortest(x);
    if (s.type == ParameterSpec::Type::Integer)
      v.integer = x >= 9.2e18    ? std::numeric_limits<long>::max()
                  : x <= -9.2e18 ? std::numeric_limits<long>::min()
                                 : static_cast<long>(x);
    else if (s.type == ParameterSpec::Type::NumberList)
      v.list = {x};
    else
      v.number = x;
    std::string problem = detail::range_problem(s, v);
    if (!problem.empty()) problems.push_back(std::move(problem));
  }
  if (problems.empty()) return;
  if (problems.size() == 1) throw Error(problems[0]);
  std::string msg = std::to_string(problems.size()) + " problems in the " + source + ":";
  for (const auto& p : problems) msg += "\n  - " + p;
  throw Error(msg);
}

}  // namespace granudrag
