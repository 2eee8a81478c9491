// HDF5 attributes: every type round trips, on groups, datasets and the root; listing and
// typing attributes not known in advance; clear errors for missing or mistyped ones.
#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

#include "io/h5_file.hpp"
#include "io_test_support.hpp"

using namespace granudrag;
using namespace granudrag::support;

TEST(H5Attributes, OnGroupsAndDatasets) {
  TempDir dir;
  const std::string path = dir.file("attrs.h5");
  {
    h5::File f = h5::File::create(path);
    f.write("/particles/all/radius/value", ramp(5));
    f.set_attr("/particles/all/radius/value", "unit", std::string("d"));
    f.set_attr("/parameters", "dt", 1.05e-5);  // creates the group
    f.set_attr("/parameters", "steps", std::int64_t{1} << 40);
    f.set_attr("/parameters", "grains", std::size_t{20000});  // any integer type
    f.set_attr("/parameters", "threads", 2);
    f.set_attr("/parameters", "empty", std::string());
    f.set_attr("/parameters", "note", "first");  // a literal works too
    f.set_attr("/parameters", "note", std::string("replaced, \xC3\xA9t\xC3\xA9"));
    f.set_attr("/particles/all/box", "boundary", std::vector<std::string>{"periodic", "periodic", "none"});
    f.set_attr("/particles/all/box", "dimension", 3);
    f.set_attr("/", "root_attr", -1.5);
    f.commit();
  }
  const h5::File f = h5::File::open(path);
  EXPECT_EQ(f.get_attr_string("/particles/all/radius/value", "unit"), "d");
  EXPECT_EQ(f.get_attr_double("/parameters", "dt"), 1.05e-5);
  EXPECT_EQ(f.get_attr_int64("/parameters", "steps"), std::int64_t{1} << 40);
  EXPECT_EQ(f.get_attr_int64("/parameters", "grains"), 20000);
  EXPECT_EQ(f.get_attr_int64("/parameters", "threads"), 2);
  EXPECT_EQ(f.get_attr_string("/parameters", "empty"), "");
  EXPECT_EQ(f.get_attr_string("/parameters", "note"), "replaced, \xC3\xA9t\xC3\xA9");
  EXPECT_EQ(f.get_attr_strings("/particles/all/box", "boundary"),
            (std::vector<std::string>{"periodic", "periodic", "none"}));
  EXPECT_EQ(f.get_attr_double("/", "root_attr"), -1.5);
  EXPECT_TRUE(f.has_attr("/parameters", "dt"));
  EXPECT_FALSE(f.has_attr("/parameters", "mu"));
  EXPECT_FALSE(f.has_attr("/nowhere", "dt"));

  const std::string missing = error_of([&] { f.get_attr_double("/parameters", "mu"); });
  EXPECT_MENTIONS(missing, "'mu'");
  EXPECT_MENTIONS(missing, "/parameters");
  EXPECT_MENTIONS(missing, path);
  const std::string no_object = error_of([&] { f.get_attr_double("/nowhere", "dt"); });
  EXPECT_MENTIONS(no_object, "/nowhere");
  const std::string wrong_type = error_of([&] { f.get_attr_int64("/parameters", "dt"); });
  EXPECT_MENTIONS(wrong_type, "'dt'");
  EXPECT_MENTIONS(wrong_type, "64-bit floats");
  EXPECT_MENTIONS(error_of([&] { f.get_attr_double("/parameters", "note"); }), "strings");
  EXPECT_MENTIONS(error_of([&] { f.get_attr_string("/particles/all/box", "boundary"); }), "get_attr_strings");
  EXPECT_MENTIONS(error_of([&] { f.get_attr_string("/parameters", "steps"); }), "not strings");
}

TEST(H5Attributes, FlagsListsAndTypesOfAttributesNotKnownInAdvance) {
  TempDir dir;
  const std::string path = dir.file("typed.h5");
  {
    h5::File f = h5::File::create(path);
    f.create_group("/parameters/empty");
    f.set_flag_attr("/parameters/pull", "resume", true);
    f.set_flag_attr("/parameters/pull", "quiet", false);
    f.set_attr("/parameters/pull", "speeds", std::vector<double>{0.1, 1, 2.5});
    f.set_attr("/parameters/pull", "none", std::vector<double>{});
    f.set_attr("/parameters/pull", "one", std::vector<double>{7});
    f.set_attr("/parameters/pull", "speed", 0.7);
    f.set_attr("/parameters/pull", "snapshots", 3);
    f.set_attr("/parameters/pull", "bed", "bed.h5");
    f.set_attr("/parameters/pull", "ids", std::vector<std::int64_t>{1, 2});
    f.commit();
  }
  const h5::File f = h5::File::open(path);
  EXPECT_TRUE(f.exists("/parameters/empty"));
  EXPECT_TRUE(f.attr_names("/parameters/empty").empty());
  EXPECT_EQ(f.attr_names("/parameters/pull"),
            (std::vector<std::string>{"bed", "ids", "none", "one", "quiet", "resume", "snapshots", "speed",
                                      "speeds"}));
  EXPECT_TRUE(f.get_attr_flag("/parameters/pull", "resume"));
  EXPECT_FALSE(f.get_attr_flag("/parameters/pull", "quiet"));
  EXPECT_EQ(f.get_attr_doubles("/parameters/pull", "speeds"), (std::vector<double>{0.1, 1, 2.5}));
  EXPECT_TRUE(f.get_attr_doubles("/parameters/pull", "none").empty());

  using T = h5::File::AttrType;
  auto shape = [&](const char* name) { return f.attr_shape("/parameters/pull", name); };
  EXPECT_EQ(shape("resume").type, T::Flag);
  EXPECT_TRUE(shape("resume").scalar);
  EXPECT_EQ(shape("speed").type, T::Float);
  EXPECT_TRUE(shape("speed").scalar);
  EXPECT_EQ(shape("speeds").type, T::Float);
  EXPECT_FALSE(shape("speeds").scalar);
  EXPECT_EQ(shape("speeds").count, 3u);
  EXPECT_FALSE(shape("one").scalar);  // a list of one number is not a number
  EXPECT_EQ(shape("none").count, 0u);
  EXPECT_EQ(shape("snapshots").type, T::Integer);
  EXPECT_EQ(shape("bed").type, T::String);
  EXPECT_EQ(shape("ids").type, T::Integer);
  EXPECT_FALSE(shape("ids").scalar);

  EXPECT_MENTIONS(error_of([&] { f.get_attr_flag("/parameters/pull", "snapshots"); }), "not a flag");
  EXPECT_MENTIONS(error_of([&] { f.get_attr_int64("/parameters/pull", "resume"); }), "enumerations");
  EXPECT_MENTIONS(error_of([&] { f.attr_names("/parameters/nowhere"); }), "/parameters/nowhere");
}
