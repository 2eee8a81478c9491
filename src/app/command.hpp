#pragma once
// What every subcommand shares: reading its key table from the command line (with --help and
// --schema), the keys several commands have (output, threads, quiet, the contact law), and small
// checks. Each subcommand lives in its own file, <name>_command.cpp, with its table.
#include <optional>
#include <string>
#include <vector>

#include "contact/contact_keys.hpp"
#include "contact/contact_params.hpp"
#include "core/parameters.hpp"
#include "protocol/pour.hpp"

namespace granudrag {

struct PullSpec;  // protocol/pull.hpp

// A subcommand: `granudrag <name>`; run() returns the exit code and throws granudrag::Error for
// anything the user can fix.
struct Command {
  const char* name;
  int (*run)(const std::vector<std::string>& args);
};
const std::vector<Command>& commands();

int pour_command(const std::vector<std::string>& args);
int pull_command(const std::vector<std::string>& args);
int place_command(const std::vector<std::string>& args);
int export_lammps_command(const std::vector<std::string>& args);
int import_lammps_command(const std::vector<std::string>& args);
int restitution_command(const std::vector<std::string>& args);
int bench_command(const std::vector<std::string>& args);
int info_command(const std::vector<std::string>& args);

// granudrag info, for tests: its keys, and the JSON object it prints for them.
std::vector<ParameterSpec> info_keys();
std::string info_json(const Parameters& par);

// `--help` or `-h` among the arguments.
bool wants_help(const std::vector<std::string>& args);

// The parameters of `granudrag <command>` from its arguments, validated. With --help it prints
// `intro`, a blank line and the key table; with --schema the keys as a JSON Schema; both times it
// returns nothing and the command exits with 0.
std::optional<Parameters> read_parameters(const std::string& command, std::vector<ParameterSpec> keys,
                                          const std::string& intro, const std::vector<std::string>& args);

// Keys several commands share.
ParameterSpec output_key(const std::string& help);  // required text
ParameterSpec threads_key();                        // OpenMP threads, 0: OMP_NUM_THREADS or all
ParameterSpec quiet_key();                          // no progress lines

// The contact law the contact keys (contact/contact_keys.hpp) give: K_n (default the paper's 2e8)
// with K_t, gamma_n, gamma_t at the paper's ratios, or Young's modulus and Poisson's ratio; each
// of kt, gamman, gammat overrides its part.
ContactParams contact_from(const Parameters& p);

void set_threads(const Parameters& p);
// The directory of `path` (the value of `key`) must exist.
void check_output_dir(const std::string& path, const std::string& key);

// The speed of a pull: --speed, or --froude for an intruder of diameter D (the inverse of
// froude_number), or 1 sqrt(gd) when neither is given.
double pull_speed(const Parameters& p, double intruder_diameter);

// The active region's radius, d: --active_radius, or --active_diameters times D.
double pull_active_radius(const Parameters& p, double intruder_diameter);

// The time step of a pull through `bed`: the bed's dt, or with spec.collision_steps = N (not
// NaN: --collision_steps given) the Hertz collision time of two of its smallest grains at the
// reference speed over N (checked as a pour's dt is).
double pull_time_step(const PullSpec& spec, const Bed& bed);

}  // namespace granudrag
