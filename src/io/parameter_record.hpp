#pragma once
// Provenance by key: the resolved parameters of the command that made a file, stored as typed
// HDF5 attributes that h5py reads as they are (f["parameters/pour"].attrs["lx"]).
//
//   /parameters/<command>         one attribute per key that has a value (given or default):
//                                   Number      float64
//                                   Integer     int64
//                                   Text        string (fixed length, UTF-8 when not ASCII)
//                                   Flag        8-bit enum {FALSE = 0, TRUE = 1}: h5py's bool
//                                   NumberList  1-D float64 array
//                                 A key without a value (no default, not given) is absent.
//   /parameters/<command>/units   the unit of each key that has one, as a string attribute
//                                 ("d", "sqrt(d/g)"; units of rho, d and g).
//
// A bed file holds /parameters/pour; a run file its bed's /parameters/pour (copied) and its own
// /parameters/pull; a checkpoint both. Files of format version 1 held one YAML text instead,
// /parameters attribute `yaml`: see ParameterRecord::legacy_yaml.
#include <cstdint>
#include <string>
#include <vector>

#include "core/parameters.hpp"
#include "io/h5_file.hpp"

namespace granudrag {

// One key's value as recorded.
struct RecordedParameter {
  std::string key;
  ParameterSpec::Type type = ParameterSpec::Type::Number;
  std::string unit;  // "" for dimensionless (or not recorded)
  double number = 0;
  std::int64_t integer = 0;
  std::string text;
  bool flag = false;
  std::vector<double> numbers;

  // The value as in a YAML file: 0.7, 3, "bed.h5", true, [0.1, 1].
  std::string value_text() const;
  // Same type and the same value, bit for bit (as a resumed pull needs).
  bool same_value(const RecordedParameter& other) const;
};

struct ParameterRecord {
  std::string command;                    // "pour", "pull": the group under /parameters
  std::vector<RecordedParameter> values;  // the keys that have a value
  // For a record read from a file of format version 1: its /parameters text, verbatim. It is
  // carried into new files for people to read (as /parameters attribute `<command>_yaml_v1`);
  // no program parses it.
  std::string legacy_yaml;

  // Every key of `parameters` that has a value, in the order of its specs.
  static ParameterRecord of(const Parameters& parameters);
  const RecordedParameter* find(const std::string& key) const;
};

// Writes /parameters/<record.command> (and its units), or for a legacy record the text.
void write_parameters(h5::File& file, const ParameterRecord& record);
bool has_parameters(const h5::File& file, const std::string& command);
// Reads /parameters/<command>; an attribute of a type no key can have is an Error naming it.
ParameterRecord read_parameters(const h5::File& file, const std::string& command);

// Every key whose value differs between `then` and `now` (a key absent on one side shows as
// ~), keys in `ignored` aside, one pair of lines each:
//   "\n  <then_label>: speed: 0.5\n  <now_label>: speed: 0.7" (labels padded to one width).
// Empty when the two agree.
std::string describe_differences(const ParameterRecord& then, const ParameterRecord& now,
                                 const std::vector<std::string>& ignored, const std::string& then_label,
                                 const std::string& now_label);

}  // namespace granudrag
