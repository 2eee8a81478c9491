// Checksums (file format version 3): every dataset with data carries HDF5's Fletcher-32 filter,
// so a bit flipped inside a dataset's stored bytes of a bed, run or checkpoint file is named on
// read (file, dataset, "regenerate it") instead of read as other data. Beds of older versions
// still load, with a note. The flips here land inside the data (chunk offsets from HDF5), where
// the random flips of test_fuzz_readers.cpp mostly hit headers and free space.
#include <gtest/gtest.h>
#include <hdf5.h>

#include <cstdio>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include "core/parameters.hpp"
#include "io/file_header.hpp"
#include "io/h5_file.hpp"
#include "io/run_files.hpp"
#include "io_test_support.hpp"
#include "protocol/pour.hpp"

using namespace granudrag;
using namespace granudrag::support;

namespace {

// Where a dataset's chunks lie in the file: (offset, stored size) per chunk.
struct Stored {
  std::string path;
  std::vector<std::pair<haddr_t, hsize_t>> chunks;
  int filters = 0;
  bool has_checksum = false;
};

herr_t collect(hid_t, const char* name, const H5O_info_t* info, void* data) {
  if (info->type == H5O_TYPE_DATASET)
    static_cast<std::vector<std::string>*>(data)->push_back("/" + std::string(name));
  return 0;
}

std::vector<Stored> stored_datasets(const std::string& file) {
  std::vector<std::string> names;
  const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
#if H5_VERSION_GE(1, 12, 0)
  H5Ovisit(f, H5_INDEX_NAME, H5_ITER_NATIVE, collect, &names, H5O_INFO_BASIC);
#else
  H5Ovisit(f, H5_INDEX_NAME, H5_ITER_NATIVE, collect, &names);
#endif
  std::vector<Stored> out;
  for (const std::string& name : names) {
    Stored s{name, {}, 0, false};
    const hid_t d = H5Dopen2(f, name.c_str(), H5P_DEFAULT);
    const hid_t dcpl = H5Dget_create_plist(d);
    s.filters = H5Pget_nfilters(dcpl);
    for (int k = 0; k < s.filters; ++k) {
      unsigned flags = 0;
      std::size_t n = 0;
      if (H5Pget_filter2(dcpl, static_cast<unsigned>(k), &flags, &n, nullptr, 0, nullptr, nullptr) ==
          H5Z_FILTER_FLETCHER32)
        s.has_checksum = true;
    }
    if (H5Pget_layout(dcpl) == H5D_CHUNKED) {
      const hid_t space = H5Dget_space(d);
      hsize_t chunks = 0;
      H5Dget_num_chunks(d, space, &chunks);
      for (hsize_t c = 0; c < chunks; ++c) {
        std::vector<hsize_t> offset(static_cast<std::size_t>(H5Sget_simple_extent_ndims(space)));
        unsigned mask = 0;
        haddr_t addr = 0;
        hsize_t size = 0;
        H5Dget_chunk_info(d, space, c, offset.data(), &mask, &addr, &size);
        s.chunks.emplace_back(addr, size);
      }
      H5Sclose(space);
    }
    H5Pclose(dcpl);
    H5Dclose(d);
    out.push_back(s);
  }
  H5Fclose(f);
  return out;
}

// Reads one dataset whole, through h5::File where it has a reader for its type and shape.
void read_dataset(const std::string& file, const std::string& path) {
  // Its type and shape first, with the file closed again: HDF5 refuses a second open of a file
  // with another close degree than h5::File's.
  const hid_t raw = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  const hid_t d = H5Dopen2(raw, path.c_str(), H5P_DEFAULT);
  const hid_t type = H5Dget_type(d), space = H5Dget_space(d);
  const int rank = H5Sget_simple_extent_ndims(space);
  std::vector<hsize_t> dims(static_cast<std::size_t>(rank));
  H5Sget_simple_extent_dims(space, dims.data(), nullptr);
  const H5T_class_t cls = H5Tget_class(type);
  const std::size_t size = H5Tget_size(type);
  H5Sclose(space);
  H5Tclose(type);
  H5Dclose(d);
  H5Fclose(raw);
  ASSERT_GE(rank, 1) << path;
  const h5::File f = h5::File::open(file);
  if (rank == 1 && cls == H5T_FLOAT) {
    f.read_doubles(path);
  } else if (rank == 1 && cls == H5T_INTEGER && size == 8) {
    f.read_int64(path);
  } else if (rank == 1 && cls == H5T_INTEGER && size == 4) {
    f.read_ints(path);
  } else if (rank == 1 && cls == H5T_INTEGER && size == 1) {
    f.read_uint8(path);
  } else if (rank == 2 && dims[1] == 3 && cls == H5T_FLOAT) {
    f.read_vec3(path);
  } else {
    ADD_FAILURE() << path << ": no reader for this type and shape in the test";
  }
}

Parameters parameters(const std::string& command,
                      const std::vector<std::pair<std::string, std::string>>& keys) {
  std::vector<ParameterSpec> specs;
  for (const auto& [key, value] : keys) {
    ParameterSpec s;
    s.key = key;
    s.type = ParameterSpec::Type::Text;
    s.default_value = value;
    s.help = key;
    specs.push_back(s);
  }
  Parameters p(command, specs);
  p.apply_cli({});
  return p;
}

// The bed, run and checkpoint files of pulled_bed(), written into dir: {bed, run, checkpoint}.
struct Written {
  std::string bed, run, checkpoint;
};
Written write_files(const TempDir& dir, const Parameters& pour_p, const Parameters& pull_p) {
  const PulledBed& fx = pulled_bed();
  const Written w{dir.file("bed.h5"), dir.file("run.h5"), dir.file("ckpt.h5")};
  save_bed(w.bed, fx.bed, pour_p);
  save_run(w.run, *fx.pull, pull_p, ParameterRecord::of(pour_p), "sanity\n");
  save_checkpoint(w.checkpoint, *fx.pull, pull_p, ParameterRecord::of(pour_p));
  return w;
}

}  // namespace

TEST(Checksums, EveryDatasetWithDataOfABedRunAndCheckpointCarriesOne) {
  TempDir dir;
  const Written w = write_files(dir, parameters("pour", {{"lx", "4"}}), parameters("pull", {{"speed", "1"}}));
  for (const std::string& file : {w.bed, w.run, w.checkpoint}) {
    EXPECT_EQ(h5::File::open(file).get_attr_int64("/granudrag", "version"), kFileVersion);
    long with_data = 0;
    for (const Stored& s : stored_datasets(file)) {
      if (s.chunks.empty()) continue;  // empty: nothing to protect
      ++with_data;
      EXPECT_TRUE(s.has_checksum) << file << ": " << s.path;
    }
    EXPECT_GT(with_data, 5) << file;
  }
}

TEST(Checksums, ABitFlippedInsideAnyDatasetsDataIsNamedOnReadAndTheReadersNeverPassItOn) {
  TempDir dir;
  const Parameters pull_p = parameters("pull", {{"speed", "1"}});
  const Written w = write_files(dir, parameters("pour", {{"lx", "4"}}), pull_p);
  const std::vector<std::pair<std::string, std::function<void(const std::string&)>>> readers = {
      {w.bed, [](const std::string& p) { load_bed(p); }},
      {w.run, [](const std::string& p) { h5::File::open(p).read_series("/observables/intruder_force"); }},
      {w.checkpoint, [&](const std::string& p) { load_checkpoint(p, pulled_bed().bed, pull_p, {}); }},
  };
  const std::string copy = dir.file("damaged.h5");
  std::mt19937_64 rng(2026);
  long cases = 0, domain_errors = 0;
  for (const auto& [file, domain_read] : readers) {
    const std::string bytes = read_bytes(file);
    for (const Stored& s : stored_datasets(file)) {
      for (const auto& [addr, size] : s.chunks) {
        // 16 flips per chunk, each in a fresh copy.
        for (int k = 0; k < 16; ++k) {
          std::string b = bytes;
          const std::size_t at = static_cast<std::size_t>(addr + rng() % size);
          b[at] = static_cast<char>(b[at] ^ (1 << (rng() % 8)));
          write_bytes(copy, b);
          ++cases;
          try {
            read_dataset(copy, s.path);
            ADD_FAILURE() << file << ": a bit flipped at byte " << at << " inside " << s.path << " was read";
          } catch (const Error& e) {
            const std::string m = e.what();
            EXPECT_NE(m.find("checksum"), std::string::npos) << m;
            EXPECT_NE(m.find(s.path), std::string::npos) << m;
            EXPECT_NE(m.find(copy), std::string::npos) << m;
            EXPECT_NE(m.find("regenerate"), std::string::npos) << m;
          }
          try {  // what a user's command makes of it: a named error, or a read of intact data
            domain_read(copy);
          } catch (const Error&) {
            ++domain_errors;
          } catch (const std::exception& e) {
            ADD_FAILURE() << s.path << ": a non-granudrag exception: " << e.what();
          }
        }
      }
    }
  }
  std::printf(
      "bit flips inside datasets: %ld cases, every flipped dataset refused on read; the bed, run "
      "and checkpoint readers stopped on %ld of them (the rest in data they do not read)\n",
      cases, domain_errors);
  EXPECT_GE(cases, 1000);
  EXPECT_GT(domain_errors, cases / 3);
}

TEST(Checksums, ABedOfAnOlderVersionStillLoadsWithANoteThatItCarriesNone) {
  TempDir dir;
  const std::string bed = dir.file("bed.h5");
  save_bed(bed, pulled_bed().bed, parameters("pour", {{"lx", "4"}}));
  {
    const hid_t f = H5Fopen(bed.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    const hid_t g = H5Gopen2(f, "/granudrag", H5P_DEFAULT);
    const hid_t a = H5Aopen(g, "version", H5P_DEFAULT);
    const std::int64_t two = 2;
    H5Awrite(a, H5T_NATIVE_INT64, &two);
    H5Aclose(a);
    H5Gclose(g);
    H5Fclose(f);
  }
  testing::internal::CaptureStderr();
  const Bed b = load_bed(bed);
  const std::string note = testing::internal::GetCapturedStderr();
  EXPECT_EQ(b.state.particles.size(), pulled_bed().bed.state.particles.size());
  EXPECT_NE(note.find("carries no checksums"), std::string::npos) << note;
}
