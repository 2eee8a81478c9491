#pragma once
// A key table bound to the struct its keys fill (PourSpec, PullSpec): each row is a key
// (parameter_spec.hpp) and, for a key that is a plain field, that field. Reading parsed
// parameters into the struct, checking a struct against the keys' ranges, and each key's default
// are then loops over the rows, and adding a key is one row plus its use:
//
//   Key::number("distance").unit("d").at_least(0).help("travel").field(&PullSpec::distance)
//   Key::number("active_radius").unit("d").help("...").field(&PullSpec::active,
//   &ActiveRegionSettings::radius)
//
// A bound row's default is the field's initial value in the struct (PullSpec{}.distance), so the
// default is written once, where the struct is; a row that states a default as well (a key that
// other commands share) must state the same one. A number field whose initial value is NaN is an
// optional key: no default, read only when given, checked only when not NaN.
//
// Rows without a field stay in the table for the command line, --help and --schema: keys that are
// an alternative to another (froude), or that the command turns into something else (the intruder
// position, defaulting to the box centre). The command reads those itself.
#include <cmath>
#include <functional>
#include <optional>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "core/parameter_spec.hpp"
#include "core/parameters.hpp"

namespace granudrag {

template <class Spec>
struct BoundKey {
  BoundKey(ParameterSpec row) : spec(std::move(row)) {}  // NOLINT: a row without a field
  BoundKey(Key row) : spec(std::move(row)) {}            // NOLINT

  // A key the command reads itself, such as one of two alternatives (speed or froude): its field
  // is still checked, but the row has no default, since a key with a default is always given.
  BoundKey read_by_command() && {
    read = nullptr;
    spec.default_value.clear();
    return std::move(*this);
  }

  ParameterSpec spec;
  // Sets the field from the parameters; empty without a field or for a key the command reads.
  std::function<void(const Parameters&, Spec&)> read;
  // The field as a number for its range check; nullopt for text, a flag, or an optional key not
  // given. Empty without a field.
  std::function<std::optional<double>(const Spec&)> number;
  // The field as it would be written on the command line ("0.02", "3", "true"); empty without a
  // field.
  std::function<std::string(const Spec&)> text;
  // Sets a double field to a value read back from a file (the bed's /contact group), not from
  // parsed parameters: also for a key the command reads. Empty without a field or for a field of
  // another type.
  std::function<void(Spec&, double)> set_number;
};

template <class Spec>
class KeyTable {
 public:
  KeyTable(std::initializer_list<BoundKey<Spec>> rows) : rows_(rows) {}

  const std::vector<BoundKey<Spec>>& rows() const { return rows_; }
  std::vector<ParameterSpec> specs() const {
    std::vector<ParameterSpec> out;
    for (const auto& r : rows_) out.push_back(r.spec);
    return out;
  }
  operator std::vector<ParameterSpec>() const { return specs(); }  // NOLINT: implicit by design

  // Every field whose key the table reads, from `parameters` (validated) into `spec`.
  void read(const Parameters& parameters, Spec& spec) const {
    for (const auto& r : rows_)
      if (r.read) r.read(parameters, spec);
  }

  // Every field within its key's range, and each of `more` (keys of rows without a field, with
  // the values the command gave them); one Error listing every problem (check_ranges). `source`
  // says where the values came from.
  void check(const Spec& spec, const std::string& source,
             const std::vector<std::pair<std::string, double>>& more = {}) const {
    std::vector<std::pair<std::string, double>> values;
    for (const auto& r : rows_)
      if (r.number)
        if (const auto x = r.number(spec)) values.emplace_back(r.spec.key, *x);
    values.insert(values.end(), more.begin(), more.end());
    check_ranges(specs(), values, source);
  }

  // A command's own keys among the struct's, in the order its files record them and --help
  // prints them.
  KeyTable& add_front(const std::vector<ParameterSpec>& rows) {
    rows_.insert(rows_.begin(), rows.begin(), rows.end());
    return *this;
  }
  KeyTable& add_before(const std::string& key, const std::vector<ParameterSpec>& rows) {
    for (auto at = rows_.begin(); at != rows_.end(); ++at)
      if (at->spec.key == key) {
        rows_.insert(at, rows.begin(), rows.end());
        return *this;
      }
    throw std::logic_error("no key '" + key + "' in this key table to add keys before");
  }
  KeyTable& add(const std::vector<ParameterSpec>& rows) {
    rows_.insert(rows_.end(), rows.begin(), rows.end());
    return *this;
  }

 private:
  std::vector<BoundKey<Spec>> rows_;
};

namespace detail {

inline std::string field_text(double v) { return number_text(v); }
inline std::string field_text(bool v) { return v ? "true" : "false"; }
inline std::string field_text(const std::string& v) { return v; }
template <class T, class = std::enable_if_t<std::is_integral_v<T>>>
std::string field_text(T v) {
  return std::to_string(v);
}

template <class T>
constexpr ParameterSpec::Type field_type() {
  if constexpr (std::is_same_v<T, double>) return ParameterSpec::Type::Number;
  if constexpr (std::is_same_v<T, bool>) return ParameterSpec::Type::Flag;
  if constexpr (std::is_same_v<T, std::string>) return ParameterSpec::Type::Text;
  return ParameterSpec::Type::Integer;
}

// `access(spec)` is the field. The row's type must be the field's, and a default the row states
// must be the field's initial value: both are code bugs otherwise (std::logic_error, raised when
// the table is first built, which every test of the command does).
template <class Spec, class T, class Access>
BoundKey<Spec> bind(ParameterSpec row, Access access) {
  static_assert(std::is_same_v<T, double> || std::is_same_v<T, bool> || std::is_same_v<T, std::string> ||
                    std::is_integral_v<T>,
                "a key binds to a double, an integer, a bool or a std::string field");
  const std::string where = "key '" + row.key + "': ";
  if (row.type != field_type<T>())
    throw std::logic_error(where + "a " + type_name(row.type) + " bound to a field of type " +
                           type_name(field_type<T>()));
  const Spec defaults{};
  const T& initial = access(defaults);
  bool optional = false;
  if constexpr (std::is_same_v<T, double>) optional = std::isnan(initial);
  if (optional && !row.default_value.empty())
    throw std::logic_error(where + "the row's default " + row.default_value + " but the field starts as NaN");
  if (!optional) {
    const std::string text = field_text(initial);
    bool same = row.default_value == text;
    if constexpr (std::is_same_v<T, double>) same = same || parse_double(row.default_value) == initial;
    if (!row.default_value.empty() && !same)
      throw std::logic_error(where + "the row's default " + row.default_value + ", the field's " + text);
    if (row.default_value.empty()) row.default_value = text;
  }
  BoundKey<Spec> b(std::move(row));
  const std::string key = b.spec.key;
  b.read = [access, key, optional](const Parameters& p, Spec& s) {
    if (optional && !p.is_set(key)) return;
    if constexpr (std::is_same_v<T, double>)
      access(s) = p.number(key);
    else if constexpr (std::is_same_v<T, bool>)
      access(s) = p.flag(key);
    else if constexpr (std::is_same_v<T, std::string>)
      access(s) = p.text(key);
    else
      access(s) = static_cast<T>(p.integer(key));
  };
  b.number = [access, optional](const Spec& s) -> std::optional<double> {
    if constexpr (std::is_same_v<T, double>) {
      if (optional && std::isnan(access(s))) return std::nullopt;
      return access(s);
    } else if constexpr (std::is_integral_v<T> && !std::is_same_v<T, bool>) {
      return static_cast<double>(access(s));
    } else {
      return std::nullopt;
    }
  };
  b.text = [access](const Spec& s) { return field_text(access(s)); };
  if constexpr (std::is_same_v<T, double>) b.set_number = [access](Spec& s, double v) { access(s) = v; };
  return b;
}

}  // namespace detail

template <class Spec, class T>
BoundKey<Spec> Key::field(T Spec::*member) && {
  return detail::bind<Spec, T>(
      std::move(*this), [member](auto& s) -> auto& { return s.*member; });
}

template <class Spec, class Group, class T>
BoundKey<Spec> Key::field(Group Spec::*group, T Group::*member) && {
  return detail::bind<Spec, T>(
      std::move(*this), [ group, member ](auto& s) -> auto& { return (s.*group).*member; });
}

}  // namespace granudrag
