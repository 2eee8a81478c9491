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

void write_frames_xdmf(const std::string& xdmf_path, const std::string& h5_file_name, std::size_t n,
                       const std::vector<double>& times) {
  if (h5_file_name.empty() || h5_file_name.find(':') != std::string::npos)
    throw Error("cannot write '" + xdmf_path + "': the HDF5 file name '" + h5_file_name +
                "' is empty or contains ':', which XDMF uses to separate file and dataset");
  if (n == 0 || times.empty()) throw Error("cannot write '" + xdmf_path + "': there are no frames to show");
  const std::size_t frames = times.size();
  std::ostringstream s;
  s.precision(17);
  s << "<?xml version=\"1.0\" ?>\n<!DOCTYPE Xdmf SYSTEM \"Xdmf.dtd\" []>\n<Xdmf Version=\"3.0\">\n  "
       "<Domain>\n";
  // Vertex i is point i: the Xdmf3 readers build no cells without the list (xdmf.cpp), and it
  // is the same for every frame, so it is stored once and referenced.
  s << "    <DataItem Name=\"vertices\" Dimensions=\"" << n
    << "\" NumberType=\"Int\" Precision=\"8\" Format=\"XML\">";
  for (std::size_t i = 0; i < n; ++i) s << (i % 20 == 0 ? "\n     " : " ") << i;
  s << "\n    </DataItem>\n";
  s << "    <Grid Name=\"frames\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
  const std::string file = xml_escape(h5_file_name) + ":/particles/frames/";
  // One frame of a [frames x n x 3] dataset: a hyperslab (start, stride, count) declared n x 3,
  // the rank ParaView's reader expects of a geometry or a vector attribute.
  auto slab = [&](std::size_t k, const std::string& element) {
    std::ostringstream d;
    d << "<DataItem ItemType=\"HyperSlab\" Dimensions=\"" << n << " 3\" Type=\"HyperSlab\">"
      << "<DataItem Dimensions=\"3 3\" Format=\"XML\">" << k << " 0 0 1 1 1 1 " << n << " 3</DataItem>"
      << "<DataItem Dimensions=\"" << frames << ' ' << n << " 3\" NumberType=\"Float\" Precision=\"8\" "
      << "Format=\"HDF\">" << file << element << "/value</DataItem></DataItem>";
    return d.str();
  };
  for (std::size_t k = 0; k < frames; ++k) {
    s << "      <Grid Name=\"frame " << k << "\" GridType=\"Uniform\">\n"
      << "        <Time Value=\"" << times[k] << "\"/>\n"
      << "        <Topology TopologyType=\"Polyvertex\" NumberOfElements=\"" << n
      << "\" NodesPerElement=\"1\">"
      << "<DataItem Reference=\"XML\">/Xdmf/Domain/DataItem[@Name=\"vertices\"]</DataItem></Topology>\n"
      << "        <Geometry GeometryType=\"XYZ\">" << slab(k, "position") << "</Geometry>\n"
      << "        <Attribute Name=\"velocity\" AttributeType=\"Vector\" Center=\"Node\">"
      << slab(k, "velocity") << "</Attribute>\n"
      << "        <Attribute Name=\"radius\" AttributeType=\"Scalar\" Center=\"Node\"><DataItem Dimensions=\""
      << n << "\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">" << file
      << "radius/value</DataItem></Attribute>\n"
      << "        <Attribute Name=\"species\" AttributeType=\"Scalar\" Center=\"Node\"><DataItem "
         "Dimensions=\""
      << n << "\" NumberType=\"UChar\" Precision=\"1\" Format=\"HDF\">" << file
      << "species/value</DataItem></Attribute>\n"
      << "      </Grid>\n";
  }
  s << "    </Grid>\n  </Domain>\n</Xdmf>\n";
  write_file_atomically(xdmf_path, s.str());
}

}  // namespace granudrag
