#pragma once
// XDMF 3 sidecars: a small XML file next to a run file that lets ParaView (or VisIt) open the
// particles of an HDF5 file as a point cloud, without a plugin and without copying data.
#include <cstddef>
#include <string>
#include <vector>

namespace granudrag {

// Writes `xdmf_path` (atomically: tmp + rename) describing the particles of
// `h5_file_name:/particles/<particle_group>` as n_particles Polyvertex points located by
// position/value (an N x 3 double dataset), with one point attribute per field:
// `<field>/value`, N doubles for each scalar field, N x 3 doubles for each vector field and N
// unsigned bytes for each byte field (species: 0 mobile grain, 1 frozen base, 2 intruder).
// Each dataset holds one frame: its rank must be exactly the declared one (ParaView's Xdmf3
// reader aborts on [1 x N x 3] declared as [N x 3]). The vertex list 0..N-1 is written out,
// about 6 bytes per particle, because the Xdmf3 readers make no cells without it.
// h5_file_name is resolved from the directory of the xdmf file, so the two can be moved
// together; it must not contain ':' (XDMF splits file and dataset there).
void write_xdmf(const std::string& xdmf_path, const std::string& h5_file_name,
                const std::string& particle_group, std::size_t n_particles,
                const std::vector<std::string>& scalar_fields, const std::vector<std::string>& vector_fields,
                const std::vector<std::string>& byte_fields = {});

// Writes `xdmf_path` (atomically), a temporal collection of `times.size()` frames of `n`
// bodies read from `h5_file_name` (resolved from the sidecar's directory) under
// /particles/frames: geometry from position, attributes velocity, radius and species.
void write_frames_xdmf(const std::string& xdmf_path, const std::string& h5_file_name, std::size_t n,
                       const std::vector<double>& times);

}  // namespace granudrag
