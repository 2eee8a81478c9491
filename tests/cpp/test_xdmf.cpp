// The XDMF sidecar points at datasets that exist, with the shapes ParaView needs.
#include <gtest/gtest.h>

#include <regex>
#include <string>
#include <vector>

#include "io/h5_file.hpp"
#include "io/xdmf.hpp"
#include "io_test_support.hpp"

using namespace granudrag;
using namespace granudrag::support;

namespace {

// Checks that every element opened is closed in order: enough to catch a broken writer
// without an XML parser.
bool tags_balanced(const std::string& xml, std::string& why) {
  std::vector<std::string> open;
  for (std::size_t i = xml.find('<'); i != std::string::npos; i = xml.find('<', i + 1)) {
    const std::size_t end = xml.find('>', i);
    if (end == std::string::npos) return why = "unterminated tag", false;
    const std::string tag = xml.substr(i + 1, end - i - 1);
    if (tag.empty() || tag[0] == '?' || tag[0] == '!') continue;
    if (tag[0] == '/') {
      if (open.empty() || open.back() != tag.substr(1))
        return why = "unexpected </" + tag.substr(1) + ">", false;
      open.pop_back();
    } else if (tag.back() != '/') {
      open.push_back(tag.substr(0, tag.find(' ')));
    }
  }
  if (!open.empty()) return why = "<" + open.back() + "> never closed", false;
  return true;
}

}  // namespace

TEST(Xdmf, PointsAtDatasetsThatExistWithTheDeclaredShapes) {
  TempDir dir;
  const std::size_t n = 250;
  const std::string h5_path = dir.file("bed.h5");
  {
    h5::File f = h5::File::create(h5_path);
    h5::write_h5md_header(f, "0.1.0", "Test Author");
    f.write_rows("/particles/all/position/value", std::vector<Vec3>(n, Vec3(1, 2, 3)));
    f.write_rows("/particles/all/velocity/value", std::vector<Vec3>(n, Vec3(0, 0, -1)));
    f.write("/particles/all/radius/value", std::vector<double>(n, 0.5));
    f.write("/particles/all/species/value", std::vector<std::uint8_t>(n, 2));
    f.commit();
  }
  const std::string xdmf_path = dir.file("bed.xdmf");
  write_xdmf(xdmf_path, "bed.h5", "all", n, {"radius"}, {"velocity"}, {"species"});
  EXPECT_FALSE(fs::exists(xdmf_path + ".tmp"));
  const std::string xml = read_text(xdmf_path);

  EXPECT_EQ(xml.rfind("<?xml version=\"1.0\" ?>", 0), 0u);
  EXPECT_MENTIONS(xml, "<Xdmf Version=\"3.0\">");
  EXPECT_MENTIONS(xml, "<Grid Name=\"all\" GridType=\"Uniform\">");
  EXPECT_MENTIONS(xml, "TopologyType=\"Polyvertex\" NumberOfElements=\"250\"");
  EXPECT_MENTIONS(xml, "<Geometry GeometryType=\"XYZ\">");
  EXPECT_MENTIONS(xml, "<Attribute Name=\"radius\" AttributeType=\"Scalar\" Center=\"Node\">");
  EXPECT_MENTIONS(xml, "<Attribute Name=\"velocity\" AttributeType=\"Vector\" Center=\"Node\">");
  EXPECT_MENTIONS(xml, "<Attribute Name=\"species\" AttributeType=\"Scalar\" Center=\"Node\">");
  EXPECT_MENTIONS(xml, "<DataItem Dimensions=\"250\" NumberType=\"UChar\" Precision=\"1\" Format=\"HDF\">");
  std::string why;
  EXPECT_TRUE(tags_balanced(xml, why)) << why << "\n" << xml;
  // Explicit vertex i = point i: without it ParaView's Xdmf3 readers load points but no cells.
  const std::size_t conn =
      xml.find("<DataItem Dimensions=\"250\" NumberType=\"Int\" Precision=\"8\" Format=\"XML\">");
  ASSERT_NE(conn, std::string::npos) << xml;
  std::istringstream indices(xml.substr(xml.find('>', conn) + 1));
  for (std::size_t i = 0; i < n; ++i) {
    std::size_t k = n;
    indices >> k;
    ASSERT_EQ(k, i);
  }

  // Every DataItem names bed.h5 and a dataset in it of exactly the declared dimensions.
  const std::regex item("<DataItem Dimensions=\"([0-9 ]+)\"[^>]*Format=\"HDF\">([^:<]+):([^<]+)</DataItem>");
  const h5::File f = h5::File::open(h5_path);
  std::vector<std::string> datasets;
  for (auto it = std::sregex_iterator(xml.begin(), xml.end(), item); it != std::sregex_iterator(); ++it) {
    const std::string dims = (*it)[1], file = (*it)[2], dataset = (*it)[3];
    datasets.push_back(dataset);
    EXPECT_EQ(file, "bed.h5");
    EXPECT_TRUE(f.exists(dataset)) << dataset;
    if (dims == "250 3") {
      EXPECT_EQ(f.read_vec3(dataset).size(), n) << dataset;
    } else if (dataset.find("species") != std::string::npos) {
      EXPECT_EQ(dims, "250");
      EXPECT_EQ(f.read_uint8(dataset).size(), n) << dataset;
    } else {
      EXPECT_EQ(dims, "250");
      EXPECT_EQ(f.read_doubles(dataset).size(), n) << dataset;
    }
  }
  EXPECT_EQ(datasets,
            (std::vector<std::string>{"/particles/all/position/value", "/particles/all/radius/value",
                                      "/particles/all/velocity/value", "/particles/all/species/value"}));
}

TEST(Xdmf, RefusesWhatParaViewCouldNotRead) {
  TempDir dir;
  const std::string x = dir.file("bad.xdmf");
  EXPECT_MENTIONS(error_of([&] { write_xdmf(x, "a:b.h5", "all", 10, {}, {}); }), "':'");
  EXPECT_MENTIONS(error_of([&] { write_xdmf(x, "b.h5", "all", 0, {}, {}); }), "no particles");
  EXPECT_MENTIONS(error_of([&] { write_xdmf(x, "b.h5", "", 10, {}, {}); }), "particle group");
  EXPECT_MENTIONS(error_of([&] { write_xdmf(x, "b.h5", "all", 10, {"a/b"}, {}); }), "'a/b'");
  EXPECT_FALSE(fs::exists(x));
  const std::string no_dir = dir.file("no/such/dir/bed.xdmf");
  EXPECT_MENTIONS(error_of([&] { write_xdmf(no_dir, "b.h5", "all", 10, {}, {}); }), no_dir);
}
