#pragma once
// The particle data the files share: a complete simulation state (bed file, checkpoint) and the
// velocity snapshots of a pull (run file, checkpoint).
//
// State, after H5MD: /particles/all/<element>/{step,time,value} for position, velocity,
// angular_velocity, force, torque (N x 3), radius (N) and species (N, uint8: 0 mobile grain,
// 1 frozen base grain, 2 intruder); the contact histories /contacts/pairs (i, j; i < j),
// /contacts/shear (N_pairs x 3) and /contacts/wall_shear (N x 3), /contacts attribute step.
#include <string>
#include <vector>

#include "engine/simulation.hpp"
#include "io/h5_file.hpp"
#include "protocol/pull.hpp"

namespace granudrag {

void write_particle_state(h5::File& file, const Simulation::State& state, double dt);
// Throws Error (without the file name: callers add it) for arrays that disagree in length,
// an unknown species or a contact pair that names no particles.
Simulation::State read_particle_state(const h5::File& file);

// Snapshot k under the group `<prefix><k>`: datasets dx, dz, vx, vz and attribute time.
void write_snapshots(h5::File& file, const std::string& prefix, const std::vector<Snapshot>& snapshots);
std::vector<Snapshot> read_snapshots(const h5::File& file, const std::string& prefix, std::size_t count);

}  // namespace granudrag
