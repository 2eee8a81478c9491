#include "io/xdmf.hpp"

#include <charconv>
#include <sstream>

#include "core/error.hpp"
#include "io/atomic_file.hpp"

namespace granudrag {

namespace {

std::string xml_escape(const std::string& s) {
  std::string out;
  for (char c : s) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      case '\'':
        out += "&apos;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

// Particle data are 64-bit floats, species unsigned bytes; ParaView needs the type spelled out.
std::string data_item(const std::string& h5_file, const std::string& dataset, std::size_t n, bool vector,
                      bool byte = false) {
  std::ostringstream s;
  s << "<DataItem Dimensions=\"" << n << (vector ? " 3" : "") << "\" NumberType=\""
    << (byte ? "UChar\" Precision=\"1" : "Float\" Precision=\"8") << "\" Format=\"HDF\">"
    << xml_escape(h5_file) << ':' << xml_escape(dataset) << "</DataItem>";
  return s.str();
}

// Vertex i is point i. ParaView's XDMF2 reader would infer that, but its Xdmf3 readers build
// no cells at all without a connectivity array (points you cannot see in Surface or Points
// view), and XDMF has no formula for 0..N-1: it is spelled out, about 6 bytes per particle.
void write_identity_connectivity(std::ostringstream& s, std::size_t n) {
  s << "        <DataItem Dimensions=\"" << n << "\" NumberType=\"Int\" Precision=\"8\" Format=\"XML\">";
  char buffer[24];
  for (std::size_t i = 0; i < n; ++i) {
    if (i % 20 == 0) s << "\n         ";
    buffer[0] = ' ';
    const auto end = std::to_chars(buffer + 1, buffer + sizeof buffer, i).ptr;
    s.write(buffer, end - buffer);
  }
  s << "\n        </DataItem>\n";
}

void check_name(const std::string& name, const char* what, const std::string& xdmf_path) {
  if (name.empty() || name.find('/') != std::string::npos)
    throw Error("cannot write '" + xdmf_path + "': " + what + " '" + name +
                "' must be a non-empty name without '/'");
}

}  // namespace

void write_xdmf(const std::string& xdmf_path, const std::string& h5_file_name,
                const std::string& particle_group, std::size_t n_particles,
                const std::vector<std::string>& scalar_fields, const std::vector<std::string>& vector_fields,
                const std::vector<std::string>& byte_fields) {
  if (h5_file_name.empty() || h5_file_name.find(':') != std::string::npos)
    throw Error("cannot write '" + xdmf_path + "': the HDF5 file name '" + h5_file_name +
                "' is empty or contains ':', which XDMF uses to separate file and dataset");
  if (n_particles == 0) throw Error("cannot write '" + xdmf_path + "': there are no particles to show");
  check_name(particle_group, "particle group", xdmf_path);
  for (const auto& f : scalar_fields) check_name(f, "field", xdmf_path);
  for (const auto& f : vector_fields) check_name(f, "field", xdmf_path);
  for (const auto& f : byte_fields) check_name(f, "field", xdmf_path);

  const std::string group = "/particles/" + particle_group + "/";
  std::ostringstream s;
  s << "<?xml version=\"1.0\" ?>\n"
    << "<!DOCTYPE Xdmf SYSTEM \"Xdmf.dtd\" []>\n"
    << "<Xdmf Version=\"3.0\">\n"
    << "  <Domain>\n"
    << "    <Grid Name=\"" << xml_escape(particle_group) << "\" GridType=\"Uniform\">\n"
    << "      <Topology TopologyType=\"Polyvertex\" NumberOfElements=\"" << n_particles
    << "\" NodesPerElement=\"1\">\n";
  write_identity_connectivity(s, n_particles);
  s << "      </Topology>\n"
    << "      <Geometry GeometryType=\"XYZ\">\n"
    << "        " << data_item(h5_file_name, group + "position/value", n_particles, true) << "\n"
    << "      </Geometry>\n";
  auto attribute = [&](const std::string& field, bool vector, bool byte = false) {
    s << "      <Attribute Name=\"" << xml_escape(field) << "\" AttributeType=\""
      << (vector ? "Vector" : "Scalar") << "\" Center=\"Node\">\n"
      << "        " << data_item(h5_file_name, group + field + "/value", n_particles, vector, byte) << "\n"
      << "      </Attribute>\n";
  };
  for (const auto& f : scalar_fields) attribute(f, false);
  for (const auto& f : vector_fields) attribute(f, true);
  for (const auto& f : byte_fields) attribute(f, false, true);
  s << "    </Grid>\n"
    << "  </Domain>\n"
    << "</Xdmf>\n";
  write_file_atomically(xdmf_path, s.str());
}

}  // namespace granudrag
