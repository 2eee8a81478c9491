#include "io/bed_file.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iterator>

#include "contact/contact_keys.hpp"
#include "core/error.hpp"
#include "io/file_header.hpp"
#include "io/particle_data.hpp"
#include "io/xdmf.hpp"

namespace granudrag {

namespace {

const char* kBedFormat = "granudrag-bed";

// The contact law's attributes every bed has had. A contact key added later is absent from the
// beds poured before it, which were poured without its term: reading one leaves the field at its
// initial value, so a new key's default must be the law as it was (contact/contact_keys.cpp).
const char* const kFirstContactKeys[] = {"kn", "kt", "gamman", "gammat", "mu"};

bool always_written(const std::string& key) {
  return std::find(std::begin(kFirstContactKeys), std::end(kFirstContactKeys), key) !=
         std::end(kFirstContactKeys);
}

}  // namespace

void write_bed_groups(h5::File& f, const Bed& bed) {
  write_particle_state(f, bed.state, bed.dt);
  f.set_attr("/box", "lx", bed.box.lx);
  f.set_attr("/box", "ly", bed.box.ly);
  f.set_attr("/box", "wall", static_cast<std::int64_t>(bed.box.wall));
  // One attribute per contact key bound to a field: the pull's contact law is the bed's, so a
  // field left out here would be lost between the pour and the pull.
  for (const auto& [key, value] : contact_fields(bed.contact)) f.set_attr("/contact", key, value);
  f.set_attr("/contact", "dt", bed.dt);
  f.set_attr("/bed", "intruder", static_cast<std::int64_t>(bed.intruder));
  f.set_attr("/bed", "surface_height", bed.surface_height);
  f.set_attr(
      "/bed", "surface_definition",
      std::string("height where the packing fraction of the grains (slabs of 0.1 d) falls to half its bulk "
                  "value; bulk = median over slabs from 2 d above the wall to 4 d below the bed top (highest "
                  "slab denser than a tenth of the densest), slabs cut by the intruder left out"));
  f.set_attr("/bed", "depth", bed.depth);
  f.set_attr("/bed", "requested_depth", bed.requested_depth);
  f.set_attr("/bed", "stop_reason", bed.stop_reason);
  f.set_attr("/bed", "kinetic_energy_per_grain", bed.kinetic_energy);
  f.set_attr("/bed", "settle_time", bed.settle_time);
  f.set_attr("/bed", "sanity", bed.sanity);
  f.set_attr("/bed", "bulk_packing_fraction", bed.profile.bulk_packing_fraction);
  f.write("/bed/profile/z", bed.profile.z);
  f.write("/bed/profile/packing_fraction", bed.profile.packing_fraction);
}

Bed read_bed_groups(const h5::File& f) {
  Bed bed;
  bed.state = read_particle_state(f);
  bed.box.lx = f.get_attr_double("/box", "lx");
  bed.box.ly = f.get_attr_double("/box", "ly");
  bed.box.wall = f.get_attr_int64("/box", "wall") != 0;
  for (const auto& row : contact_keys().rows())
    if (row.set_number && (always_written(row.spec.key) || f.has_attr("/contact", row.spec.key)))
      row.set_number(bed.contact, f.get_attr_double("/contact", row.spec.key));
  bed.dt = f.get_attr_double("/contact", "dt");
  bed.intruder = static_cast<int>(f.get_attr_int64("/bed", "intruder"));
  const Particles& p = bed.state.particles;
  if (bed.intruder >= static_cast<int>(p.size()) || bed.intruder < -1 ||
      (bed.intruder >= 0 && p.species[bed.intruder] != Species::Intruder))
    throw Error("/bed/intruder = " + std::to_string(bed.intruder) + " is not the index of an intruder");
  for (std::size_t i = 0; i < p.size(); ++i)
    if (!(p.radius[i] > 0) || !std::isfinite(p.radius[i]) || !p.x[i].allFinite())
      throw Error("particle " + std::to_string(i) + " has a bad radius or position");
  if (!(bed.box.lx > 0) || !(bed.box.ly > 0) || !(bed.dt > 0))
    throw Error("bad box or time step under /box, /contact");
  bed.surface_height = f.get_attr_double("/bed", "surface_height");
  bed.depth = f.get_attr_double("/bed", "depth");
  bed.requested_depth = f.get_attr_double("/bed", "requested_depth");
  bed.stop_reason = f.get_attr_string("/bed", "stop_reason");
  bed.kinetic_energy = f.get_attr_double("/bed", "kinetic_energy_per_grain");
  bed.settle_time = f.get_attr_double("/bed", "settle_time");
  if (f.has_attr("/bed", "sanity")) bed.sanity = f.get_attr_string("/bed", "sanity");  // absent if imported
  bed.profile.bulk_packing_fraction = f.get_attr_double("/bed", "bulk_packing_fraction");
  bed.profile.z = f.read_doubles("/bed/profile/z");
  bed.profile.packing_fraction = f.read_doubles("/bed/profile/packing_fraction");
  bed.profile.surface_height = bed.surface_height;
  return bed;
}

void save_bed(const std::string& path, const Bed& bed, const Parameters& parameters, FrameDump* frames) {
  h5::File f = h5::File::create(path);
  write_file_header(f, kBedFormat);
  write_parameters(f, ParameterRecord::of(parameters));
  write_bed_groups(f, bed);
  if (frames) frames->write_into(f);
  f.commit();
}

void save_placed_bed(const std::string& path, const Bed& bed, const ParameterRecord& source,
                     const Parameters& parameters, const std::string& source_path,
                     const PlacementRecord& record) {
  h5::File f = h5::File::create(path);
  write_file_header(f, kBedFormat);
  write_parameters(f, source);
  write_parameters(f, ParameterRecord::of(parameters));
  write_bed_groups(f, bed);
  f.set_attr("/placement", "source", source_path);
  f.write("/placement/removed", std::vector<std::int64_t>(record.removed.begin(), record.removed.end()));
  f.set_attr("/placement", "source_surface_height", record.source_surface_height);
  f.set_attr("/placement", "source_kinetic_energy_per_grain", record.source_kinetic_energy);
  f.set_attr("/placement", "intruder_z", record.intruder_z);
  f.commit();
}

Bed load_bed(const std::string& path, ParameterRecord* parameters, ParameterRecord* placement) {
  const h5::File f = h5::File::open(path);
  const std::int64_t version = check_file_header(f, kBedFormat, 1, "re-create it with this granudrag");
  if (version < kFirstChecksummedVersion)
    std::fprintf(stderr,
                 "note: bed file '%s' (format version %lld) carries no checksums: damage to its data "
                 "cannot be detected; pour it again with this granudrag to get them\n",
                 path.c_str(), static_cast<long long>(version));
  try {
    Bed bed = read_bed_groups(f);
    if (parameters != nullptr) {
      if (version == 1) {  // the parameters as one YAML text: kept for people, not parsed
        *parameters = ParameterRecord{};
        parameters->command = "pour";
        parameters->legacy_yaml = f.get_attr_string("/parameters", "yaml");
      } else {
        const bool poured = has_parameters(f, "pour");
        if (!poured && !has_parameters(f, "import-lammps"))
          throw Error("no /parameters/pour (nor /parameters/import-lammps): what made the bed is unknown");
        *parameters = read_parameters(f, poured ? "pour" : "import-lammps");
      }
    }
    if (placement != nullptr)
      *placement =
          version > 1 && has_parameters(f, "place") ? read_parameters(f, "place") : ParameterRecord{};
    return bed;
  } catch (const Error& e) {
    throw Error("bed file '" + path + "' is damaged: " + e.what());
  }
}

void write_bed_xdmf(const std::string& bed_path, std::size_t particles) {
  const std::string name = bed_path.substr(bed_path.find_last_of('/') + 1);
  write_xdmf(bed_path + ".xdmf", name, "all", particles, {"radius"}, {"velocity", "angular_velocity"},
             {"species"});
}

}  // namespace granudrag
