// granudrag info: the quantities the engine derives from its parameters, as one JSON object, so
// that scripts use (and test their formulas against) the engine's own numbers.
#include <cstdio>
#include <iostream>

#include "app/command.hpp"
#include "contact/contact_keys.hpp"
#include "core/error.hpp"
#include "protocol/pull.hpp"

namespace granudrag {

namespace {

// The grains of a pour are 0.9 d to 1.1 d: info's time step is that of the smallest possible pair.
// A pour derives its own from its smallest grain, so its dt (proportional to that radius) is
// larger by about 0.1/grains relatively (5e-5 for 2000 grains).
constexpr double kSmallestGrainRadius = 0.45;

std::string entry(const char* key, double value) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "\"%s\": %.17g", key, value);
  return buf;
}

}  // namespace

std::vector<ParameterSpec> info_keys() {
  std::vector<ParameterSpec> keys = contact_keys();
  keys.push_back(time_step_key());
  keys.push_back(Key::number("intruder_diameter")
                     .unit("d")
                     .above(0)
                     .help("D: with speed or froude, also prints the other of the two"));
  keys.push_back(find_spec(pull_keys(), "speed"));
  keys.push_back(find_spec(pull_keys(), "froude"));
  return keys;
}

std::string info_json(const Parameters& par) {
  const ContactParams c = contact_from(par);
  const double tc = shortest_collision_time(c, kSmallestGrainRadius);
  const double dt = par.is_set("dt") ? par.number("dt") : default_time_step(c, kSmallestGrainRadius);
  check_time_step(dt, c, kSmallestGrainRadius);
  // The contact law as pour resolves it, field by field (a new contact key's included), then the
  // time step's numbers.
  std::vector<std::string> entries;
  for (const auto& [key, value] : contact_fields(c)) entries.push_back(entry(key.c_str(), value));
  entries.push_back(entry("dt", dt));
  entries.push_back(entry("collision_time", tc));
  entries.push_back(entry("max_dt", tc / TimeStepPolicy::steps_per_collision_min));
  entries.push_back(entry("wake_force", default_wake_force(c.kn)));
  const bool has_speed = par.is_set("speed") || par.is_set("froude");
  if (par.is_set("intruder_diameter") != has_speed)
    throw Error("give 'intruder_diameter' together with 'speed' or 'froude' (or none of them)");
  if (has_speed) {
    const double D = par.number("intruder_diameter");
    const double V = pull_speed(par, D);
    entries.push_back(entry("intruder_diameter", D));
    entries.push_back(entry("speed", V));
    entries.push_back(entry("froude", froude_number(V, D)));
  }
  std::string out = "{";
  for (std::size_t i = 0; i < entries.size(); ++i) out += (i ? ", " : "") + entries[i];
  return out + "}\n";
}

int info_command(const std::vector<std::string>& args) {
  const auto par = read_parameters(
      "info", info_keys(),
      "granudrag info — the quantities granudrag derives, as one JSON object: the contact law (kn, kt,\n"
      "gamman, gammat, mu as pour resolves them), the default time step dt (or the given one), the Hertz\n"
      "collision time it derives from and the largest dt accepted (for two grains of 0.9 d, the smallest a\n"
      "pour holds; a pour's own dt uses its smallest grain, larger by ~0.1/grains), the active region's\n"
      "default wake_force at that kn; with --intruder_diameter and --speed or --froude also the\n"
      "intruder_diameter, speed and froude of that pull\n\n"
      "  granudrag info --kn 2e4 --intruder_diameter 2 --froude 0.5",
      args);
  if (!par) return 0;
  std::cout << info_json(*par);
  return 0;
}

}  // namespace granudrag
