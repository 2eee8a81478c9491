// granudrag: DEM of an intruder pulled through a settled granular bed (Kumar et al. 2022).
// main() only dispatches subcommands and turns errors into messages.
#include <cstdio>
#include <iostream>
#include <string>
#include <vector>

#include "app/command.hpp"
#include "core/build_stamp.hpp"
#include "core/error.hpp"

namespace {

const char* kUsage = R"(granudrag — drag on an intruder pulled through a granular bed (DEM)

Usage:
  granudrag <command> [--key value ...]
  granudrag <command> --help      (its keys: type, unit, default, range, meaning)
  granudrag <command> --schema    (the same as a JSON Schema)

Commands:
  pour       Pour grains around a fixed intruder and let them settle: writes a bed file
             (HDF5 + XDMF sidecar for ParaView).
  place      Put an intruder into a settled bed poured without one, remove the grains it
             cuts and settle the bed again: one column serves every depth and D.
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
  info       Print the quantities granudrag derives (contact law, default time step, collision
             time, largest time step; Froude number and speed of a pull) as one JSON object.
  version    Print the version and the commit it was built from.
  help       This text.

Units (everything dimensionless): grain density rho, mean grain diameter d, gravity g.
Time sqrt(d/g), speed sqrt(g d), force rho d^3 g, K_n and K_t rho d g, gamma sqrt(g/d^3).
Contact law: Hertz with tangential history, as LAMMPS gran/hertz/history (paper Eqs. 1-3).
)";

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
      std::cout << "granudrag " << GRANUDRAG_VERSION << " (commit " << granudrag::build_commit() << ")\n";
      return 0;
    }
    for (const auto& c : granudrag::commands())
      if (command == c.name) return c.run(args);
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
