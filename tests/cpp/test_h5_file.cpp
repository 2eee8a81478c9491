// HDF5 files: every type and shape round trips, attributes, series, atomic commit, clear errors
// on bad files and bad reads, and h5dump accepts the result.
#include <gtest/gtest.h>
#include <hdf5.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <regex>
#include <sstream>

#include "core/error.hpp"
#include "io/h5_file.hpp"
#include "io_test_support.hpp"

using namespace granudrag;
using namespace granudrag::support;
namespace fs = std::filesystem;

namespace {

// Writes a small file with one dataset of each kind.
void write_sample(const std::string& path) {
  h5::File f = h5::File::create(path);
  h5::write_h5md_header(f, "0.1.0", "Test Author");
  f.write("/particles/all/radius/value", ramp(100));
  f.write("/particles/all/id", std::vector<std::int64_t>{1, 2, 3});
  f.write_rows("/particles/all/position/value", std::vector<Vec3>(100, Vec3(1, 2, 3)));
  f.commit();
}

}  // namespace

TEST(H5File, RoundTripsEveryTypeAndShape) {
  TempDir dir;
  const std::string path = dir.file("types.h5");
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1e3, 1e3);
  for (std::size_t n :
       {std::size_t{0}, std::size_t{1}, std::size_t{17}, std::size_t{5000}, std::size_t{100000}}) {
    SCOPED_TRACE("n = " + std::to_string(n));
    std::vector<double> d(n);
    std::vector<std::int64_t> l(n);
    std::vector<int> i(n);
    std::vector<std::uint8_t> b(n);
    std::vector<Vec3> v(n);
    for (std::size_t k = 0; k < n; ++k) {
      d[k] = u(rng);
      l[k] = static_cast<std::int64_t>(rng());
      i[k] = static_cast<int>(rng());
      b[k] = static_cast<std::uint8_t>(rng());
      v[k] = Vec3(u(rng), u(rng), u(rng));
    }
    if (n > 3) {
      d[0] = std::numeric_limits<double>::infinity();
      d[1] = std::numeric_limits<double>::denorm_min();
      d[2] = -0.0;
      l[0] = std::numeric_limits<std::int64_t>::min();
      l[1] = std::numeric_limits<std::int64_t>::max();
      i[0] = std::numeric_limits<int>::min();
      b[0] = 255;
    }
    {
      h5::File f = h5::File::create(path);
      f.write("/a/doubles", d);
      f.write("/a/int64", l);
      f.write("/a/ints", i);
      f.write("/a/uint8", b);
      f.write_rows("/b/c/vec3", v);
      f.commit();
    }
    const h5::File f = h5::File::open(path);
    EXPECT_EQ(f.read_doubles("/a/doubles"), d);
    EXPECT_EQ(f.read_int64("/a/int64"), l);
    EXPECT_EQ(f.read_ints("/a/ints"), i);
    EXPECT_EQ(f.read_uint8("/a/uint8"), b);
    const std::vector<Vec3> back = f.read_vec3("b/c/vec3");  // the leading slash is optional
    ASSERT_EQ(back.size(), n);
    for (std::size_t k = 0; k < n; ++k) EXPECT_EQ(back[k], v[k]) << "row " << k;
  }
}

TEST(H5File, EveryArrayIsChunkedWithAChecksumAndLargeOnesAreCompressed) {
  TempDir dir;
  const std::string path = dir.file("layout.h5");
  {
    h5::File f = h5::File::create(path);
    f.write("/small", ramp(4095));
    f.write("/large", ramp(4096));
    f.write_rows("/rows", std::vector<Vec3>(2000, Vec3(0.25, 0.5, 1.0)));  // 6000 elements
    f.write("/empty", std::vector<double>{});
    f.commit();
  }
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  ASSERT_GE(file, 0);
  for (const char* name : {"/small", "/large", "/rows", "/empty"}) {
    const hid_t dset = H5Dopen2(file, name, H5P_DEFAULT);
    const hid_t dcpl = H5Dget_create_plist(dset);
    const bool big = std::string(name) == "/large" || std::string(name) == "/rows";
    const bool empty = std::string(name) == "/empty";
    EXPECT_EQ(H5Pget_layout(dcpl), empty ? H5D_CONTIGUOUS : H5D_CHUNKED) << name;
    // shuffle and deflate on the large ones, the checksum on every one with data
    EXPECT_EQ(H5Pget_nfilters(dcpl), empty ? 0 : (big ? 3 : 1)) << name;
    if (!empty) {
      unsigned flags = 0;
      std::size_t n = 0;
      const int last = H5Pget_nfilters(dcpl) - 1;
      EXPECT_EQ(H5Pget_filter2(dcpl, static_cast<unsigned>(last), &flags, &n, nullptr, 0, nullptr, nullptr),
                H5Z_FILTER_FLETCHER32)
          << name;
    }
    H5Pclose(dcpl);
    H5Dclose(dset);
  }
  H5Fclose(file);
}

// Checkpoints are written with Compression::None: large arrays are stored as they are, with
// only their checksum.
TEST(H5File, AnUncompressedFileWritesOnlyTheChecksum) {
  TempDir dir;
  const std::string path = dir.file("checkpoint.h5");
  {
    h5::File f = h5::File::create(path, h5::Compression::None);
    f.write("/large", ramp(100000));
    f.write_rows("/rows", std::vector<Vec3>(20000, Vec3(0.25, 0.5, 1.0)));
    f.commit();
  }
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  ASSERT_GE(file, 0);
  for (const char* name : {"/large", "/rows"}) {
    const hid_t dset = H5Dopen2(file, name, H5P_DEFAULT);
    const hid_t dcpl = H5Dget_create_plist(dset);
    EXPECT_EQ(H5Pget_layout(dcpl), H5D_CHUNKED) << name;
    EXPECT_EQ(H5Pget_nfilters(dcpl), 1) << name;
    H5Pclose(dcpl);
    H5Dclose(dset);
  }
  H5Fclose(file);
  EXPECT_EQ(h5::File::open(path).read_doubles("/large"), ramp(100000));
  EXPECT_GE(fs::file_size(path), 8u * (100000 + 60000));  // every byte stored as is
}

// Large arrays are compressed at gzip level 1: level 9 costs seconds per snapshot for a few
// percent of disk. Checked on the file's own filter settings, not on a wall clock (the time is
// printed for information only: this machine is shared).
TEST(H5File, WritesLargeArraysWithCheapCompression) {
  TempDir dir;
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(0, 100);
  std::vector<Vec3> x(200000);
  for (auto& p : x) p = Vec3(u(rng), u(rng), u(rng));
  const auto t0 = std::chrono::steady_clock::now();
  h5::File f = h5::File::create(dir.file("big.h5"));
  f.write_rows("/particles/all/position/value", x);
  f.commit();
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf("  200000 x 3 random doubles written and committed in %.3f s (%.1f MB on disk)\n", seconds,
              fs::file_size(dir.file("big.h5")) / 1e6);
  const hid_t file = H5Fopen(dir.file("big.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  ASSERT_GE(file, 0);
  const hid_t dset = H5Dopen2(file, "/particles/all/position/value", H5P_DEFAULT);
  ASSERT_GE(dset, 0);
  const hid_t dcpl = H5Dget_create_plist(dset);
  bool deflate = false;
  for (int k = 0; k < H5Pget_nfilters(dcpl); ++k) {
    unsigned flags = 0, level[4] = {0, 0, 0, 0};
    std::size_t n = 4;
    char name[64];
    if (H5Pget_filter2(dcpl, static_cast<unsigned>(k), &flags, &n, level, sizeof name, name, nullptr) !=
        H5Z_FILTER_DEFLATE)
      continue;
    deflate = true;
    ASSERT_GE(n, 1u);
    EXPECT_EQ(level[0], 1u) << "gzip level of a large dataset";
  }
  EXPECT_TRUE(deflate) << "a 200000-row dataset is stored compressed";
  H5Pclose(dcpl);
  H5Dclose(dset);
  H5Fclose(file);
  EXPECT_EQ(h5::File::open(dir.file("big.h5")).read_vec3("/particles/all/position/value"), x);
}

TEST(H5File, GroupsAreCreatedOnDemandAndExistsSeesThem) {
  TempDir dir;
  h5::File f = h5::File::create(dir.file("groups.h5"));
  EXPECT_TRUE(f.exists("/"));
  EXPECT_FALSE(f.exists("/particles"));
  f.write("/particles/all/radius/value", ramp(3));
  EXPECT_TRUE(f.exists("/particles"));
  EXPECT_TRUE(f.exists("/particles/all"));
  EXPECT_TRUE(f.exists("particles//all/radius/value/"));
  EXPECT_FALSE(f.exists("/particles/all/mass"));
  EXPECT_FALSE(f.exists("/particles/all/radius/value/below_a_dataset"));
  EXPECT_FALSE(f.exists("/nothing/at/all"));
  const std::string twice = error_of([&] { f.write("/particles/all/radius/value", ramp(3)); });
  EXPECT_MENTIONS(twice, "/particles/all/radius/value");
  EXPECT_MENTIONS(twice, "already exists");
  const std::string under = error_of([&] { f.write("/particles/all/radius/value/x", ramp(3)); });
  EXPECT_MENTIONS(under, "/particles/all/radius/value/x");
  EXPECT_MENTIONS(under, "'/particles/all/radius/value' is a dataset, not a group");
  EXPECT_MENTIONS(error_of([&] { f.set_attr("/particles/all/radius/value/x", "a", 1.0); }),
                  "is a dataset, not a group");
  EXPECT_MENTIONS(error_of([&] { f.series("/particles/all/radius/value/x", 1); }),
                  "is a dataset, not a group");
}

TEST(H5File, ReadOnlyFilesRefuseWrites) {
  TempDir dir;
  write_sample(dir.file("ro.h5"));
  h5::File f = h5::File::open(dir.file("ro.h5"));
  EXPECT_FALSE(f.writable());
  EXPECT_MENTIONS(error_of([&] { f.write("/x", ramp(2)); }), "read-only");
  EXPECT_MENTIONS(error_of([&] { f.set_attr("/", "x", 1.0); }), "read-only");
  EXPECT_MENTIONS(error_of([&] { f.series("/observables/x", 1); }), "read-only");
  EXPECT_MENTIONS(error_of([&] { f.commit(); }), "read-only");
}

TEST(H5Series, ThousandRowsAppendedOneByOneReadBack) {
  TempDir dir;
  const std::string path = dir.file("series.h5");
  const int n = 1000;
  double seconds = 0;
  {
    h5::File f = h5::File::create(path);
    h5::Series drag = f.series("/observables/drag", 3);
    h5::Series energy = f.series("/observables/kinetic_energy", 1);
    const auto t0 = std::chrono::steady_clock::now();
    for (int k = 0; k < n; ++k) {
      const double row[3] = {1.0 * k, -2.0 * k, 0.5 + k};
      drag.append(100 * k, 1e-3 * k, row);
      energy.append(100 * k, 1e-3 * k, std::vector<double>{k * k * 1.0});
    }
    seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    EXPECT_EQ(drag.rows(), static_cast<std::size_t>(n));
    EXPECT_EQ(drag.columns(), 3u);
    f.commit();
    EXPECT_MENTIONS(error_of([&] { drag.append(n * 100, 1.0, std::vector<double>{1, 2, 3}); }), "committed");
  }
  // For information only (no assertion on a wall clock: this machine is shared).
  std::printf("  %d rows appended to 2 series in %.1f ms (%.1f us per append)\n", n, 1e3 * seconds,
              1e6 * seconds / (2 * n));

  const h5::File f = h5::File::open(path);
  const h5::SeriesData drag = f.read_series("/observables/drag");
  ASSERT_EQ(drag.rows(), static_cast<std::size_t>(n));
  ASSERT_EQ(drag.columns, 3u);
  ASSERT_EQ(drag.values.size(), 3u * n);
  for (int k = 0; k < n; ++k) {
    EXPECT_EQ(drag.steps[k], 100 * k);
    EXPECT_EQ(drag.times[k], 1e-3 * k);
    EXPECT_EQ(drag.values[3 * k + 0], 1.0 * k);
    EXPECT_EQ(drag.values[3 * k + 1], -2.0 * k);
    EXPECT_EQ(drag.values[3 * k + 2], 0.5 + k);
  }
  const h5::SeriesData energy = f.read_series("observables/kinetic_energy");
  EXPECT_EQ(energy.columns, 1u);
  ASSERT_EQ(energy.values.size(), static_cast<std::size_t>(n));
  EXPECT_EQ(energy.values[999], 999.0 * 999.0);
  // H5MD shapes: value is [rows] for one column, [rows x columns] otherwise.
  EXPECT_EQ(f.read_doubles("/observables/kinetic_energy/value").size(), static_cast<std::size_t>(n));
  EXPECT_MENTIONS(error_of([&] { f.read_doubles("/observables/drag/value"); }), "[1000 x 3]");
}

TEST(H5Series, RefusesBadRowsAndRepeatedSteps) {
  TempDir dir;
  h5::File f = h5::File::create(dir.file("bad_series.h5"));
  h5::Series s = f.series("/observables/drag", 2);
  s.append(10, 0.1, std::vector<double>{1, 2});
  const std::string repeated = error_of([&] { s.append(10, 0.2, std::vector<double>{1, 2}); });
  EXPECT_MENTIONS(repeated, "/observables/drag");
  EXPECT_MENTIONS(repeated, "steps must increase");
  EXPECT_MENTIONS(error_of([&] { s.append(11, 0.2, std::vector<double>{1, 2, 3}); }), "2 columns");
  EXPECT_MENTIONS(error_of([&] { f.series("/observables/drag", 2); }), "already exists");
  EXPECT_MENTIONS(error_of([&] { f.series("/observables/none", 0); }), "at least one column");
  s.append(11, 0.2, std::vector<double>{3, 4});  // still usable after refused appends
  EXPECT_EQ(s.rows(), 2u);
  const h5::SeriesData back = f.read_series("/observables/drag");  // readable before commit
  EXPECT_EQ(back.steps, (std::vector<std::int64_t>{10, 11}));
  EXPECT_EQ(back.values, (std::vector<double>{1, 2, 3, 4}));
  EXPECT_MENTIONS(error_of([&] { f.read_series("/observables/none"); }), "/observables/none/step");
}

TEST(H5File, CommitIsAtomic) {
  TempDir dir;
  const std::string path = dir.file("run.h5");
  const std::string tmp = path + ".tmp";
  {
    h5::File f = h5::File::create(path);
    f.write("/version", std::vector<int>{1});
    EXPECT_TRUE(fs::exists(tmp));
    EXPECT_FALSE(fs::exists(path));
    f.commit();
    EXPECT_FALSE(fs::exists(tmp));
    EXPECT_TRUE(fs::exists(path));
    EXPECT_MENTIONS(error_of([&] { f.commit(); }), "already committed");
    EXPECT_MENTIONS(error_of([&] { f.write("/x", ramp(1)); }), "committed");
  }
  {  // an abandoned rewrite leaves the committed file alone and no .tmp
    h5::File f = h5::File::create(path);
    f.write("/version", std::vector<int>{2});
    h5::Series s = f.series("/observables/x", 1);  // open objects must not keep the file alive
    s.append(0, 0.0, std::vector<double>{1});
  }
  EXPECT_FALSE(fs::exists(tmp));
  EXPECT_EQ(h5::File::open(path).read_ints("/version"), std::vector<int>{1});
  {  // an exception while writing does the same
    try {
      h5::File f = h5::File::create(path);
      f.write("/version", std::vector<int>{3});
      f.read_doubles("/no/such/thing");
    } catch (const Error&) {
    }
  }
  EXPECT_FALSE(fs::exists(tmp));
  EXPECT_EQ(h5::File::open(path).read_ints("/version"), std::vector<int>{1});
  {  // a commit replaces the old file
    h5::File f = h5::File::create(path);
    f.write("/version", std::vector<int>{4});
    f.commit();
  }
  EXPECT_EQ(h5::File::open(path).read_ints("/version"), std::vector<int>{4});
  {  // never committed and never written: nothing at all
    h5::File f = h5::File::create(dir.file("never.h5"));
  }
  EXPECT_FALSE(fs::exists(dir.file("never.h5")));
  EXPECT_FALSE(fs::exists(dir.file("never.h5.tmp")));
  {  // a moved File commits once, and its husk removes nothing
    h5::File a = h5::File::create(dir.file("moved.h5"));
    a.write("/x", ramp(2));
    h5::File b = std::move(a);
    b.commit();
  }
  EXPECT_TRUE(fs::exists(dir.file("moved.h5")));
  const std::string no_dir = error_of([&] { h5::File::create(dir.file("no/such/dir/x.h5")); });
  EXPECT_MENTIONS(no_dir, "does not exist");
}

TEST(H5File, OpeningAMissingFileNamesIt) {
  TempDir dir;
  const std::string path = dir.file("missing.h5");
  const std::string message = error_of([&] { h5::File::open(path); });
  EXPECT_MENTIONS(message, path);
  EXPECT_MENTIONS(message, "no such file");
}

TEST(H5File, OpeningATruncatedFileNamesIt) {
  TempDir dir;
  const std::string path = dir.file("truncated.h5");
  write_sample(path);
  fs::resize_file(path, fs::file_size(path) / 2);
  const std::string message = error_of([&] {
    const h5::File f = h5::File::open(path);
    f.read_vec3("/particles/all/position/value");
  });
  EXPECT_MENTIONS(message, path);
  EXPECT_MENTIONS(message, "truncated");
}

TEST(H5File, OpeningATextFileNamesIt) {
  TempDir dir;
  const std::string path = dir.file("notes.h5");
  std::ofstream(path) << "this is not HDF5\n";
  const std::string message = error_of([&] { h5::File::open(path); });
  EXPECT_MENTIONS(message, path);
  EXPECT_MENTIONS(message, "not an HDF5 file");
  const std::string empty = dir.file("empty.h5");
  std::ofstream{empty};
  EXPECT_MENTIONS(error_of([&] { h5::File::open(empty); }), "not an HDF5 file");
  EXPECT_MENTIONS(error_of([&] { h5::File::open(dir.path().string()); }), "directory");
}

TEST(H5File, WrongShapeOrTypeNamesTheDataset) {
  TempDir dir;
  const std::string path = dir.file("shapes.h5");
  {
    h5::File f = h5::File::create(path);
    f.write("/flat", ramp(6));
    f.write("/big_ints", std::vector<std::int64_t>{1, 2});
    f.write("/bytes", std::vector<std::uint8_t>{1, 2});
    f.write_rows("/rows", std::vector<Vec3>(2, Vec3::Zero()));
    f.commit();
  }
  const h5::File f = h5::File::open(path);
  const std::string not_rows = error_of([&] { f.read_vec3("/flat"); });
  EXPECT_MENTIONS(not_rows, "/flat");
  EXPECT_MENTIONS(not_rows, "[6]");
  EXPECT_MENTIONS(not_rows, "[N x 3]");
  const std::string not_flat = error_of([&] { f.read_doubles("/rows"); });
  EXPECT_MENTIONS(not_flat, "/rows");
  EXPECT_MENTIONS(not_flat, "[2 x 3]");
  const std::string float_as_int = error_of([&] { f.read_int64("/flat"); });
  EXPECT_MENTIONS(float_as_int, "/flat");
  EXPECT_MENTIONS(float_as_int, "64-bit floats");
  const std::string narrowing = error_of([&] { f.read_ints("/big_ints"); });
  EXPECT_MENTIONS(narrowing, "/big_ints");
  EXPECT_MENTIONS(narrowing, "64-bit signed integers");
  EXPECT_MENTIONS(error_of([&] { f.read_doubles("/big_ints"); }), "/big_ints");
  EXPECT_MENTIONS(error_of([&] { f.read_uint8("/big_ints"); }), "/big_ints");
  // Widening is lossless and allowed.
  EXPECT_EQ(f.read_int64("/bytes"), (std::vector<std::int64_t>{1, 2}));
  EXPECT_EQ(f.read_ints("/bytes"), (std::vector<int>{1, 2}));
  EXPECT_MENTIONS(error_of([&] { f.read_doubles("/"); }), "is a group, not a dataset");
  const std::string missing = error_of([&] { f.read_doubles("/particles/all/mass"); });
  EXPECT_MENTIONS(missing, "/particles/all/mass");
  EXPECT_MENTIONS(missing, path);
}

TEST(H5File, H5mdHeaderAndH5dumpReadsTheFile) {
  TempDir dir;
  const std::string path = dir.file("h5md.h5");
  write_sample(path);
  {
    const h5::File f = h5::File::open(path);
    EXPECT_EQ(f.get_attr_int64s("/h5md", "version"), (std::vector<std::int64_t>{1, 1}));
    EXPECT_EQ(f.get_attr_string("/h5md/creator", "name"), "granudrag");
    EXPECT_EQ(f.get_attr_string("/h5md/creator", "version"), "0.1.0");
    EXPECT_EQ(f.get_attr_string("/h5md/author", "name"), "Test Author");
  }
  {
    h5::File f = h5::File::create(dir.file("login.h5"));
    h5::write_h5md_header(f, "0.1.0");
    EXPECT_FALSE(f.get_attr_string("/h5md/author", "name").empty());
  }
  const std::string h5dump = "/usr/bin/h5dump";
  if (!fs::exists(h5dump)) GTEST_SKIP() << h5dump << " not installed (Debian package hdf5-tools)";
  const std::string out = dir.file("h5dump.txt");
  const int status = std::system((h5dump + " -H '" + path + "' > '" + out + "' 2>&1").c_str());
  const std::string dump = read_text(out);
  ASSERT_EQ(status, 0) << dump;
  EXPECT_MENTIONS(dump, "GROUP \"h5md\"");
  EXPECT_MENTIONS(dump, "GROUP \"creator\"");
  EXPECT_MENTIONS(dump, "DATASET \"value\"");
  EXPECT_MENTIONS(dump, "( 100, 3 )");
  EXPECT_MENTIONS(dump, "H5T_IEEE_F64LE");
}
