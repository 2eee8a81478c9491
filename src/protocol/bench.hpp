#pragma once
#include <functional>
#include <string>
#include <vector>

#include "contact/contact_params.hpp"
#include "core/box.hpp"
#include "core/particles.hpp"

namespace granudrag {

struct BenchOptions {
  long grains = 20000;
  long steps = 2000;
  long settle_steps = 4000;  // untimed, from the lattice to a bed in contact
  std::vector<int> threads{1, 2};
  double skin = 0.2;
  double dt = 0.0;  // 0: default for the stiffness
  double initial_speed = 0.5;
  ContactParams contact = ContactParams{}.with_stiffness(2.0e5);
  std::uint64_t seed = 1;
  // Called once with the collapsed state the timed runs start from (e.g. to write it for LAMMPS:
  // the application does that, the protocol layer knows no file formats); returns a line for the
  // table, or "".
  std::function<std::string(const Particles&, const Box&, double dt)> export_start;
};

// Lets an fcc-packed bed of `grains` grains collapse under gravity for `settle_steps` (untimed),
// then, from that state with fresh contact histories (as LAMMPS reading it would start), times
// `steps` further steps of settling with each thread count and prints particle-steps per second
// and the split between force, neighbour and integration.
void run_bench(const BenchOptions& options);

}  // namespace granudrag
