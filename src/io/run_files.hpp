#pragma once
// The files of a study, HDF5 laid out after H5MD (readable with h5py and h5dump):
//   bed file        a settled bed: complete state with contact histories, the resolved pour
//                   parameters, the surface and depth measured, the packing-fraction profile
//   run file        a pull: force series, drag and its error, n, theta, Z, P(Z), kappa,
//                   velocity snapshots, the sanity figures, the resolved parameters
//   checkpoint      a bed file plus the pull's record so far
// Every file is written under a temporary name and renamed when complete, and carries
// /granudrag attributes `format` and `version` that readers check.
#include <string>

#include "protocol/pour.hpp"
#include "protocol/pull.hpp"

namespace granudrag {

constexpr std::int64_t kFileVersion = 1;

// `parameters_yaml`: the resolved configuration (Parameters::to_yaml) stored in /parameters.
void save_bed(const std::string& path, const Bed& bed, const std::string& parameters_yaml);
// Throws Error naming the file when it is missing, truncated, not a bed file, or of another
// version. The bed's parameters_yaml is returned through the pointer when given.
Bed load_bed(const std::string& path, std::string* parameters_yaml = nullptr);

// `identity`: what a resumed pull must match (its options and the bed, see bed_fingerprint).
void save_checkpoint(const std::string& path, const Pull& pull, const std::string& parameters_yaml,
                     const std::string& identity);
struct Checkpoint {
  Simulation::State state;
  PullRecord record;
  std::string identity;
};
// A hash of a bed's particles (positions, radii, species): tells two beds apart.
std::string bed_fingerprint(const Bed& bed);
Checkpoint load_checkpoint(const std::string& path, const Bed& bed);

void save_run(const std::string& path, const Pull& pull, const std::string& parameters_yaml,
              const std::string& sanity);

// An XDMF sidecar (path with .xdmf) so ParaView opens the bed's particles.
void write_bed_xdmf(const std::string& bed_path, std::size_t particles);

}  // namespace granudrag
