#pragma once
// Interop with LAMMPS, the paper's own code: a data file (atom_style sphere) and an input
// script that runs the same contact law, so a state can be cross-checked or benchmarked there.
#include <string>

#include "contact/contact_params.hpp"
#include "core/box.hpp"
#include "core/particles.hpp"

namespace granudrag {

// Types: 1 mobile grain, 2 frozen grain, 3 intruder. Density 1, so LAMMPS' masses equal ours.
void write_lammps_data(const std::string& path, const Particles& p, const Box& box, double z_top);

struct LammpsRun {
  std::string data_file;
  ContactParams contact;
  double dt = 1e-5;
  double skin = 0.2;
  long steps = 1000;
  long thermo_every = 1000;
};
void write_lammps_settle_input(const std::string& path, const LammpsRun& run);

// The pull of a bed in LAMMPS, from a data file written by write_lammps_data: mobile grains
// integrated (nve/sphere) under gravity, the base frozen, the intruder (atom id intruder_id)
// moved at speed V along +x by fix move; the force on it written every `every` steps to
// force_file as "step fx fy fz" (averaged over the interval when every > 1).
struct LammpsPull {
  std::string data_file, force_file = "lammps_force.txt";
  ContactParams contact;
  double dt = 1e-5, skin = 0.2, speed = 1.0;
  long steps = 100, every = 1;
  long intruder_id = 0;
};
void write_lammps_pull_input(const std::string& path, const LammpsPull& run);

// Reads a LAMMPS data file of atom_style sphere (Atoms section "id type diameter density x y z
// [ix iy iz]", optional Velocities "id vx vy vz wx wy wz"). Types map to kinds: frozen_type and
// intruder_type as given (0: none), all others mobile. Density must be 1 (granudrag's units);
// the box must start at x = y = z = 0 (the wall). Throws Error naming the file and line.
struct LammpsData {
  Particles particles;
  Box box;
};
LammpsData read_lammps_data(const std::string& path, int frozen_type, int intruder_type);

}  // namespace granudrag
