// granudrag bench: settle an fcc-packed bed and time it, per thread count.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <string>

#include "app/command.hpp"
#include "app/output_paths.hpp"
#include "core/error.hpp"
#include "io/lammps_io.hpp"
#include "protocol/bench.hpp"
#include "protocol/pour.hpp"

namespace granudrag {

namespace {

std::vector<ParameterSpec> bench_keys() {
  std::vector<ParameterSpec> keys = {
      Key::integer("grains").default_value("20000").at_least(1).at_most(1e9).help(
          "number of grains, diameters uniform in [0.9, 1.1] d"),
      Key::integer("steps").default_value("2000").at_least(1).at_most(1e15).help(
          "timed steps per thread count"),
      Key::integer("settle").default_value("4000").at_least(0).at_most(1e15).help(
          "untimed steps first, collapsing the lattice into contact"),
      Key::numbers("threads").default_value("1,2").at_least(1).at_most(4096).help(
          "OpenMP thread counts to time, one run each"),
      skin_key(),
  };
  // The contact law of a pour, but softer by default: a benchmark bed settles in fewer steps.
  for (const auto& k : contact_keys().specs()) {
    if (k.key == "kn")
      keys.push_back(Key(k).default_value("2e5").help(
          "normal stiffness K_n; K_t, gamma_n, gamma_t follow it with K_t/K_n, gamma_t/gamma_n and "
          "gamma_n/K_n^0.6 of the paper fixed"));
    else
      keys.push_back(k);
  }
  keys.push_back(time_step_key());
  keys.push_back(Key::number("speed")
                     .unit("sqrt(g d)")
                     .default_value("0.5")
                     .at_least(0)
                     .help("initial random grain speed"));
  keys.push_back(Key::integer("seed").default_value("1").at_least(0).at_most(9e18).help("random seed"));
  keys.push_back(Key::text("lammps").help(
      "also write PREFIX.data and PREFIX.in: the same run for LAMMPS (lmp -in PREFIX.in), for a "
      "side-by-side comparison"));
  return keys;
}

}  // namespace

int bench_command(const std::vector<std::string>& args) {
  const auto par =
      read_parameters("bench", bench_keys(),
                      "granudrag bench — settle an fcc-packed bed and time it: particle-steps per "
                      "second and the\ntime split (force, neighbour, integration) per thread count",
                      args);
  if (!par) return 0;
  BenchOptions o;
  o.grains = par->integer("grains");
  o.steps = par->integer("steps");
  o.settle_steps = par->integer("settle");
  o.threads.clear();
  for (const double t : par->numbers("threads")) {
    if (t != std::floor(t)) {
      std::ostringstream msg;
      msg << "'threads' must be whole numbers of threads, got " << t << " (e.g. --threads 1,2)";
      throw Error(msg.str());
    }
    o.threads.push_back(static_cast<int>(t));
  }
  if (o.threads.empty())
    throw Error("'threads' is empty: give at least one thread count, e.g. --threads 1,2");
  o.skin = par->number("skin");
  o.contact = contact_from(*par);
  o.dt = par->is_set("dt") ? par->number("dt") : 0.0;
  o.initial_speed = par->number("speed");
  o.seed = static_cast<std::uint64_t>(par->integer("seed"));
  if (par->is_set("lammps")) {
    const std::string prefix = par->text("lammps");
    o.export_start = [prefix, &o](const Particles& particles, const Box& box, double dt) {
      double ztop = 0;
      for (const auto& x : particles.x) ztop = std::max(ztop, x.z() + 1.0);
      write_lammps_data(prefix + ".data", particles, box, ztop);
      LammpsRun run;
      // Relative to the input script: run lmp from the directory that holds both.
      const std::string data = prefix + ".data";
      run.data_file = data.substr(data.find_last_of('/') + 1);
      run.contact = o.contact;
      run.dt = dt;
      run.skin = o.skin;
      run.steps = o.steps;
      run.thermo_every = o.steps;
      write_lammps_settle_input(prefix + ".in", run);
      char line[256];
      std::snprintf(line, sizeof line, "# LAMMPS input: %s.in (data %s.data), dt = %.6g\n", prefix.c_str(),
                    prefix.c_str(), dt);
      return std::string(line);
    };
  }
  std::vector<OutputLock> locks;
  if (par->is_set("lammps")) {
    const std::string prefix = par->text("lammps");
    check_output_dir(prefix, "lammps");
    locks = claim_outputs(config_inputs(args), {{"the data file", prefix + ".data", "text"},
                                                {"the input script", prefix + ".in", "text"}});
  }
  run_bench(o);
  return 0;
}

}  // namespace granudrag
