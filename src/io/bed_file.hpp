#pragma once
// The bed file (`granudrag pour`, `granudrag import-lammps`): a settled bed, complete enough to
// pull from it bit for bit as the pour left it.
//   /particles, /contacts   the state with its contact histories (io/particle_data.hpp)
//   /box                    lx, ly, wall
//   /contact                kn, kt, gamman, gammat, mu (one attribute per contact key that is a
//                           ContactParams field: contact/contact_keys.cpp), dt
//   /bed                    intruder (index, -1: none), surface_height, depth, requested_depth,
//                           bulk_packing_fraction, stop_reason, kinetic_energy_per_grain,
//                           settle_time, sanity; /bed/profile/{z,packing_fraction}
//   /parameters/<command>   the resolved parameters of the command that made it, pour or
//                           import-lammps (io/parameter_record.hpp); a placed bed holds its
//                           source's and /parameters/place
//   /placement              a placed bed only (granudrag place): source (path), removed (the
//                           source's indices of the grains removed), source_surface_height,
//                           source_kinetic_energy_per_grain, intruder_z
#include <string>

#include "io/frame_dump.hpp"
#include "io/h5_file.hpp"
#include "io/parameter_record.hpp"
#include "protocol/placement.hpp"
#include "protocol/pour.hpp"

namespace granudrag {

// `parameters`: the resolved parameters of the command that made the bed.
// `frames`: the pour's frames (--dump_interval), or null.
void save_bed(const std::string& path, const Bed& bed, const Parameters& parameters,
              FrameDump* frames = nullptr);
// A bed made by placing an intruder into `source_path`'s bed: its parameters (`source`, as
// load_bed returned them) carried over beside the placement's own.
void save_placed_bed(const std::string& path, const Bed& bed, const ParameterRecord& source,
                     const Parameters& parameters, const std::string& source_path,
                     const PlacementRecord& record);
// Throws Error naming the file when it is missing, truncated, not a bed file, or of a version
// this granudrag cannot read. Reads format versions 1 and 2; the bed's recorded parameters are
// returned through `parameters` when given (for version 1: a record holding only the old text),
// and a placed bed's /parameters/place through `placement` (its command left empty for others).
Bed load_bed(const std::string& path, ParameterRecord* parameters = nullptr,
             ParameterRecord* placement = nullptr);

// An XDMF sidecar (path with .xdmf) so ParaView opens the bed's particles.
void write_bed_xdmf(const std::string& bed_path, std::size_t particles);

// The bed's groups (/particles, /contacts, /box, /contact, /bed), which a checkpoint holds too.
void write_bed_groups(h5::File& file, const Bed& bed);
// Throws Error (without the file name) for values no bed can have.
Bed read_bed_groups(const h5::File& file);

}  // namespace granudrag
