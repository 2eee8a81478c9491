// granudrag: DEM of an intruder pulled through a settled granular bed (Kumar et al. 2022).
// main() only dispatches subcommands and turns errors into messages.
#include <cstdio>
#include <iostream>
#include <string>
#include <vector>

#include "app/cli.hpp"
#include "app/commands.hpp"
#include "core/error.hpp"
#include "protocol/bench.hpp"

namespace {

const char* kUsage = R"(granudrag — drag on an intruder pulled through a granular bed (DEM)

Usage:
  granudrag <command> [--key value ...]
  granudrag <command> --help

Commands:
  pour       Pour grains around a fixed intruder and let them settle: writes a bed file
             (HDF5 + XDMF sidecar for ParaView).
  pull       Pull the intruder of a bed at constant speed: writes a run file with the force
             series, the drag and its error, n, theta, Z, P(Z), kappa, velocity snapshots.
             Checkpoints as it goes; --resume continues after a crash or kill.
  export-lammps  Write a bed as a LAMMPS data file plus an input script running the same pull
             with gran/hertz/history (the paper's own code), for cross-checks.
  import-lammps  Turn a LAMMPS data file (atom_style sphere) into a granudrag bed.
  restitution  e(v_n) of a grain hitting the wall, from the engine and from the direct
             integration of the viscoelastic Hertz equation (paper Fig. 2), as CSV.
  bench      Settle a dense bed of N grains and print particle-steps per second and the
             time split (force, neighbour, integration) for each thread count.
  version    Print the version and the commit it was built from.
  help       This text.

Units (everything dimensionless): grain density rho, mean grain diameter d, gravity g.
Time sqrt(d/g), speed sqrt(g d), force rho d^3 g, K_n and K_t rho d g, gamma sqrt(g/d^3).
Contact law: Hertz with tangential history, as LAMMPS gran/hertz/history (paper Eqs. 1-3).
)";

const char* kBenchUsage = R"(granudrag bench — settle an fcc-packed bed and time it

Options (defaults in brackets):
  --grains N        number of grains, diameters uniform in [0.9, 1.1] d        [20000]
  --steps S         timed steps per thread count                               [2000]
  --settle S        untimed steps first, collapsing the lattice into contact    [4000]
  --threads LIST    comma-separated OpenMP thread counts                       [1,2]
  --skin S          Verlet skin in d                                           [0.2]
  --kn K            normal stiffness in rho d g; K_t, gamma_n, gamma_t follow it with
                    K_t/K_n, gamma_t/gamma_n and gamma_n/K_n^0.6 of the paper fixed  [2e5]
  --mu MU           friction coefficient                                       [0.5]
  --dt DT           time step in sqrt(d/g); 0 = derived from the Hertz collision time [0]
  --speed V         initial random grain speed in sqrt(g d)                    [0.5]
  --seed N          random seed                                                [1]
  --lammps PREFIX   also write PREFIX.data and PREFIX.in: the same run for LAMMPS
                    (lmp -in PREFIX.in), for a side-by-side comparison
)";

int bench(const std::vector<std::string>& args) {
  using namespace granudrag;
  const Options opt(
      args, {"grains", "steps", "settle", "threads", "skin", "kn", "mu", "dt", "speed", "seed", "lammps"},
      "bench");
  BenchOptions o;
  o.grains = opt.integer("grains", o.grains, 1);
  o.steps = opt.integer("steps", o.steps, 1);
  o.settle_steps = opt.integer("settle", o.settle_steps, 0);
  o.threads = opt.integer_list("threads", o.threads);
  o.skin = opt.number("skin", o.skin);
  const double kn = opt.number("kn", 2.0e5);
  if (!(kn > 0)) throw Error("option '--kn' must be > 0 (got " + std::to_string(kn) + ")");
  o.contact = ContactParams{}.with_stiffness(kn);
  o.contact.mu = opt.number("mu", o.contact.mu);
  o.dt = opt.number("dt", 0.0);
  o.initial_speed = opt.number("speed", o.initial_speed);
  o.seed = static_cast<std::uint64_t>(opt.integer("seed", 1, 0));
  o.lammps_prefix = opt.text("lammps", "");
  run_bench(o);
  return 0;
}

bool wants_help(const std::vector<std::string>& args) {
  for (const auto& a : args)
    if (a == "--help" || a == "-h") return true;
  return false;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> args(argv + 1, argv + argc);
  if (args.empty() || args[0] == "help" || args[0] == "--help" || args[0] == "-h") {
    std::cout << kUsage;
    return args.empty() ? 2 : 0;
  }
  const std::string command = args[0];
  args.erase(args.begin());
  try {
    if (command == "version" || command == "--version") {
      std::cout << "granudrag " << GRANUDRAG_VERSION << " (commit " << GRANUDRAG_COMMIT << ")\n";
      return 0;
    }
    if (command == "pour") return granudrag::pour_command(args);
    if (command == "pull") return granudrag::pull_command(args);
    if (command == "export-lammps") return granudrag::export_lammps_command(args);
    if (command == "import-lammps") return granudrag::import_lammps_command(args);
    if (command == "restitution") return granudrag::restitution_command(args);
    if (command == "bench") {
      if (wants_help(args)) {
        std::cout << kBenchUsage;
        return 0;
      }
      return bench(args);
    }
    std::cerr << "granudrag: unknown command '" << command << "'. Run 'granudrag --help'.\n";
    return 2;
  } catch (const granudrag::Error& e) {
    std::cerr << "granudrag " << command << ": error: " << e.what() << "\n";
    return 1;
  } catch (const std::exception& e) {
    std::cerr << "granudrag " << command << ": internal error: " << e.what() << "\n";
    return 3;
  }
}
