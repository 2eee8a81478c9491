// Whole datasets of File: written once, read back with their rank, shape and type checked.
#include "io/h5_file.hpp"

#include <hdf5.h>

#include <algorithm>

#include "core/error.hpp"
#include "io/hdf5_internals.hpp"

namespace granudrag::h5 {

using namespace detail;

namespace {

void create_and_write(hid_t file, const std::string& file_name, bool compress, const std::string& raw_path,
                      hid_t file_type, hid_t mem_type, const std::vector<hsize_t>& dims, const void* data) {
  const std::string path = canonical(raw_path);
  if (path == "/") throw Error("cannot write a dataset at the root of " + in_quotes(file_name));
  if (object_exists(file, path))
    throw Error(in_file(path, file_name) + " already exists: each dataset is written once");
  require_group_ancestors(file, file_name, path);
  hsize_t total = 1;
  for (hsize_t d : dims) total *= d;

  Handle space(H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr), H5Sclose);
  Handle dcpl(H5Pcreate(H5P_DATASET_CREATE), H5Pclose);
  // Every dataset with data is chunked, so that it carries a checksum (an empty one has nothing
  // to protect, and a chunk may not exceed a fixed extent of 0).
  if (total > 0) {
    std::vector<hsize_t> chunk = dims;
    const hsize_t row = total / dims[0];
    chunk[0] = std::max<hsize_t>(1, std::min<hsize_t>(dims[0], kChunkElements / std::max<hsize_t>(row, 1)));
    H5Pset_chunk(dcpl.get(), static_cast<int>(chunk.size()), chunk.data());
    if (compress && total >= kCompressFrom) set_compression(dcpl.get());
    set_checksum(dcpl.get());
  }
  const Handle lcpl = link_create_plist();
  Handle dset(H5Dcreate2(file, path.c_str(), file_type, space.get(), lcpl.get(), dcpl.get(), H5P_DEFAULT),
              H5Dclose);
  if (!dset.ok()) throw Error("cannot create dataset " + in_file(path, file_name) + hdf5_reason());
  if (total > 0 && H5Dwrite(dset.get(), mem_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) < 0)
    throw Error("cannot write dataset " + in_file(path, file_name) + hdf5_reason() + " (disk full?)");
}

}  // namespace

void File::write(const std::string& path, const std::vector<double>& data) {
  create_and_write(id(true), path_, compression_ == Compression::Gzip, path, H5T_IEEE_F64LE,
                   H5T_NATIVE_DOUBLE, {data.size()}, data.data());
}

void File::write(const std::string& path, const std::vector<std::int64_t>& data) {
  create_and_write(id(true), path_, compression_ == Compression::Gzip, path, H5T_STD_I64LE, H5T_NATIVE_INT64,
                   {data.size()}, data.data());
}

void File::write(const std::string& path, const std::vector<int>& data) {
  create_and_write(id(true), path_, compression_ == Compression::Gzip, path, H5T_STD_I32LE, H5T_NATIVE_INT,
                   {data.size()}, data.data());
}

void File::write(const std::string& path, const std::vector<std::uint8_t>& data) {
  create_and_write(id(true), path_, compression_ == Compression::Gzip, path, H5T_STD_U8LE, H5T_NATIVE_UINT8,
                   {data.size()}, data.data());
}

void File::write_rows(const std::string& path, const std::vector<Vec3>& rows) {
  create_and_write(id(true), path_, compression_ == Compression::Gzip, path, H5T_IEEE_F64LE,
                   H5T_NATIVE_DOUBLE, {rows.size(), 3}, rows.empty() ? nullptr : rows.front().data());
}

std::vector<double> File::read_doubles(const std::string& path) const {
  return read_1d<double>(id(false), path_, path, Want::Float);
}

std::vector<std::int64_t> File::read_int64(const std::string& path) const {
  return read_1d<std::int64_t>(id(false), path_, path, Want::Int64);
}

std::vector<int> File::read_ints(const std::string& path) const {
  return read_1d<int>(id(false), path_, path, Want::Int);
}

std::vector<std::uint8_t> File::read_uint8(const std::string& path) const {
  return read_1d<std::uint8_t>(id(false), path_, path, Want::UInt8);
}

std::vector<Vec3> File::read_vec3(const std::string& path) const {
  const Dataset d = open_dataset(id(false), path_, path, Want::Float);
  require_shape(d, path_, 2, 3, "[N x 3] (one x, y, z row per vector)");
  std::vector<Vec3> out(d.dims[0]);
  if (!out.empty() &&
      H5Dread(d.dset.get(), H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.front().data()) < 0)
    throw Error("cannot read dataset " + in_file(d.path, path_) + read_failure());
  return out;
}

}  // namespace granudrag::h5
