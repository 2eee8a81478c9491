#include "io/parameter_record.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "core/error.hpp"

namespace granudrag {

namespace {

using Type = ParameterSpec::Type;

// The fewest digits that read back as the same double: 0.7, 2e+08, 1e-05.
std::string shortest(double v) {
  char buf[40];
  for (int digits = 1; digits <= 17; ++digits) {
    std::snprintf(buf, sizeof buf, "%.*g", digits, v);
    if (std::strtod(buf, nullptr) == v) break;
  }
  return buf;
}

std::string quoted(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + "\"";
}

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

std::string group_of(const std::string& command) { return "/parameters/" + command; }

}  // namespace

std::string RecordedParameter::value_text() const {
  switch (type) {
    case Type::Number:
      return shortest(number);
    case Type::Integer:
      return std::to_string(integer);
    case Type::Text:
      return quoted(text);
    case Type::Flag:
      return flag ? "true" : "false";
    case Type::NumberList: {
      std::string out = "[";
      for (std::size_t k = 0; k < numbers.size(); ++k) out += (k ? ", " : "") + shortest(numbers[k]);
      return out + "]";
    }
  }
  return "";
}

bool RecordedParameter::same_value(const RecordedParameter& other) const {
  if (type != other.type) return false;
  switch (type) {
    case Type::Number:
      return same_bits(number, other.number);
    case Type::Integer:
      return integer == other.integer;
    case Type::Text:
      return text == other.text;
    case Type::Flag:
      return flag == other.flag;
    case Type::NumberList:
      return numbers.size() == other.numbers.size() &&
             std::equal(numbers.begin(), numbers.end(), other.numbers.begin(), same_bits);
  }
  return false;
}

ParameterRecord ParameterRecord::of(const Parameters& parameters) {
  ParameterRecord record;
  record.command = parameters.command();
  for (const ParameterSpec& spec : parameters.specs()) {
    if (!parameters.is_set(spec.key)) continue;
    RecordedParameter r;
    r.key = spec.key;
    r.type = spec.type;
    r.unit = spec.unit;
    switch (spec.type) {
      case Type::Number:
        r.number = parameters.number(spec.key);
        break;
      case Type::Integer:
        r.integer = parameters.integer(spec.key);
        break;
      case Type::Text:
        r.text = parameters.text(spec.key);
        break;
      case Type::Flag:
        r.flag = parameters.flag(spec.key);
        break;
      case Type::NumberList:
        r.numbers = parameters.numbers(spec.key);
        break;
    }
    record.values.push_back(std::move(r));
  }
  return record;
}

const RecordedParameter* ParameterRecord::find(const std::string& key) const {
  for (const RecordedParameter& r : values)
    if (r.key == key) return &r;
  return nullptr;
}

void write_parameters(h5::File& file, const ParameterRecord& record) {
  if (record.command.empty() || record.command.find('/') != std::string::npos)
    throw Error("parameters recorded without a valid command name ('" + record.command + "')");
  if (!record.legacy_yaml.empty() && record.values.empty()) {
    file.set_attr("/parameters", record.command + "_yaml_v1", record.legacy_yaml);
    return;
  }
  const std::string group = group_of(record.command);
  file.create_group(group);  // present even when no key has a value
  for (const RecordedParameter& r : record.values) {
    switch (r.type) {
      case Type::Number:
        file.set_attr(group, r.key, r.number);
        break;
      case Type::Integer:
        file.set_attr(group, r.key, r.integer);
        break;
      case Type::Text:
        file.set_attr(group, r.key, r.text);
        break;
      case Type::Flag:
        file.set_flag_attr(group, r.key, r.flag);
        break;
      case Type::NumberList:
        file.set_attr(group, r.key, r.numbers);
        break;
    }
    if (!r.unit.empty()) file.set_attr(group + "/units", r.key, r.unit);
  }
}

bool has_parameters(const h5::File& file, const std::string& command) {
  return file.exists(group_of(command));
}

ParameterRecord read_parameters(const h5::File& file, const std::string& command) {
  using AttrType = h5::File::AttrType;
  ParameterRecord record;
  record.command = command;
  const std::string group = group_of(command);
  const std::string units = group + "/units";
  const bool has_units = file.exists(units);
  for (const std::string& key : file.attr_names(group)) {
    const h5::File::AttrShape shape = file.attr_shape(group, key);
    RecordedParameter r;
    r.key = key;
    if (shape.type == AttrType::Float && shape.scalar) {
      r.type = Type::Number;
      r.number = file.get_attr_double(group, key);
    } else if (shape.type == AttrType::Float) {
      r.type = Type::NumberList;
      r.numbers = file.get_attr_doubles(group, key);
    } else if (shape.type == AttrType::Integer && shape.scalar) {
      r.type = Type::Integer;
      r.integer = file.get_attr_int64(group, key);
    } else if (shape.type == AttrType::String && shape.scalar) {
      r.type = Type::Text;
      r.text = file.get_attr_string(group, key);
    } else if (shape.type == AttrType::Flag && shape.scalar) {
      r.type = Type::Flag;
      r.flag = file.get_attr_flag(group, key);
    } else {
      throw Error("attribute '" + key + "' on '" + group + "' in '" + file.path() +
                  "' is not a parameter value (a number, an integer, a string, a flag or a list of "
                  "numbers)");
    }
    if (has_units && file.has_attr(units, key)) r.unit = file.get_attr_string(units, key);
    record.values.push_back(std::move(r));
  }
  return record;
}

std::string describe_differences(const ParameterRecord& then, const ParameterRecord& now,
                                 const std::vector<std::string>& ignored, const std::string& then_label,
                                 const std::string& now_label) {
  std::vector<std::string> keys;
  for (const ParameterRecord* record : {&now, &then})
    for (const RecordedParameter& r : record->values)
      if (std::find(keys.begin(), keys.end(), r.key) == keys.end() &&
          std::find(ignored.begin(), ignored.end(), r.key) == ignored.end())
        keys.push_back(r.key);
  const std::size_t width = std::max(then_label.size(), now_label.size()) + 1;
  auto label = [width](const std::string& l) { return l + ":" + std::string(width - l.size(), ' '); };
  std::string out;
  for (const std::string& key : keys) {
    const RecordedParameter* a = then.find(key);
    const RecordedParameter* b = now.find(key);
    if (a != nullptr && b != nullptr && a->same_value(*b)) continue;
    out += "\n  " + label(then_label) + key + ": " + (a ? a->value_text() : "~");
    out += "\n  " + label(now_label) + key + ": " + (b ? b->value_text() : "~");
  }
  return out;
}

}  // namespace granudrag
