#pragma once
#include <string>
#include <vector>

#include "contact/contact_params.hpp"

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
  std::string lammps_prefix;  // when set, also write <prefix>.data and <prefix>.in
};

// Lets an fcc-packed bed of `grains` grains collapse under gravity for `settle_steps` (untimed),
// then, from that state with fresh contact histories (as LAMMPS reading it would start), times
// `steps` further steps of settling with each thread count and prints particle-steps per second
// and the split between force, neighbour and integration.
void run_bench(const BenchOptions& options);

}  // namespace granudrag
