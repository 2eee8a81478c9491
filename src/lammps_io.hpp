#pragma once
// Interop with LAMMPS, the paper's own code: a data file (atom_style sphere) and an input
// script that runs the same contact law, so a state can be cross-checked or benchmarked there.
#include <string>

#include "box.hpp"
#include "contact_params.hpp"
#include "particles.hpp"

namespace granudrag {

// Types: 1 mobile grain, 2 frozen grain, 3 intruder. Density 1, so LAMMPS' masses equal ours.
void write_lammps_data(const std::string& path, const Particles& p, const Box& box,
                       double z_top);

struct LammpsRun {
  std::string data_file;
  ContactParams contact;
  double dt = 1e-5;
  double skin = 0.2;
  long steps = 1000;
  long thermo_every = 1000;
};
void write_lammps_settle_input(const std::string& path, const LammpsRun& run);

// Writes to path + ".tmp" and renames, so a reader never sees half a file.
void write_file_atomically(const std::string& path, const std::string& content);

}  // namespace granudrag
