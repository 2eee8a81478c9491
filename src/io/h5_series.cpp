// Series: H5MD time-dependent elements written one row at a time, and read back whole.
#include "io/h5_file.hpp"

#include <hdf5.h>

#include <algorithm>

#include "core/error.hpp"
#include "io/hdf5_internals.hpp"

namespace granudrag::h5 {

using namespace detail;

namespace {

Handle create_extendible(hid_t file, const std::string& file_name, const std::string& path, hid_t file_type,
                         hsize_t columns, bool two_d) {
  const hsize_t dims[2] = {0, columns};
  const hsize_t max_dims[2] = {H5S_UNLIMITED, columns};
  const int rank = two_d ? 2 : 1;
  const hsize_t rows = std::max<hsize_t>(1, std::min<hsize_t>(kSeriesChunkRows, kChunkElements / columns));
  const hsize_t chunk[2] = {rows, columns};
  const Handle space(H5Screate_simple(rank, dims, max_dims), H5Sclose);
  const Handle dcpl(H5Pcreate(H5P_DATASET_CREATE), H5Pclose);
  H5Pset_chunk(dcpl.get(), rank, chunk);
  set_compression(dcpl.get());
  const Handle lcpl = link_create_plist();
  Handle dset(H5Dcreate2(file, path.c_str(), file_type, space.get(), lcpl.get(), dcpl.get(), H5P_DEFAULT),
              H5Dclose);
  if (!dset.ok()) throw Error("cannot create dataset " + in_file(path, file_name) + hdf5_reason());
  return dset;
}

// Grows `dset` to `row + 1` rows and writes `columns` values into the new row.
bool append_row(hid_t dset, hid_t mem_type, const void* data, hsize_t row, hsize_t columns) {
  const hsize_t dims[2] = {row + 1, columns};
  if (H5Dset_extent(dset, dims) < 0) return false;
  const Handle file_space(H5Dget_space(dset), H5Sclose);
  const hsize_t start[2] = {row, 0};
  const hsize_t count[2] = {1, columns};
  if (H5Sselect_hyperslab(file_space.get(), H5S_SELECT_SET, start, nullptr, count, nullptr) < 0) return false;
  const Handle mem_space(H5Screate_simple(1, &columns, nullptr), H5Sclose);
  return H5Dwrite(dset, mem_type, mem_space.get(), file_space.get(), H5P_DEFAULT, data) >= 0;
}

}  // namespace

Series File::series(const std::string& group, std::size_t columns) {
  const hid_t file = id(true);
  const std::string g = canonical(group);
  if (columns == 0) throw Error("series " + in_file(g, path_) + " needs at least one column");
  for (const char* part : {"/step", "/time", "/value"}) {
    const std::string p = (g == "/" ? "" : g) + part;
    if (object_exists(file, p))
      throw Error(in_file(p, path_) + " already exists: each series is started once");
  }
  const std::string base = g == "/" ? "" : g;
  require_group_ancestors(file, path_, base + "/step");
  Series s;
  s.file_ = path_;
  s.group_ = g;
  s.columns_ = columns;
  s.step_ = create_extendible(file, path_, base + "/step", H5T_STD_I64LE, 1, false).release();
  s.time_ = create_extendible(file, path_, base + "/time", H5T_IEEE_F64LE, 1, false).release();
  s.value_ = create_extendible(file, path_, base + "/value", H5T_IEEE_F64LE, columns, columns > 1).release();
  return s;
}

Series::Series(Series&& other) noexcept
    : step_(std::exchange(other.step_, -1)),
      time_(std::exchange(other.time_, -1)),
      value_(std::exchange(other.value_, -1)),
      columns_(other.columns_),
      rows_(other.rows_),
      last_step_(other.last_step_),
      file_(std::move(other.file_)),
      group_(std::move(other.group_)) {}

Series& Series::operator=(Series&& other) noexcept {
  if (this != &other) {
    release();
    step_ = std::exchange(other.step_, -1);
    time_ = std::exchange(other.time_, -1);
    value_ = std::exchange(other.value_, -1);
    columns_ = other.columns_;
    rows_ = other.rows_;
    last_step_ = other.last_step_;
    file_ = std::move(other.file_);
    group_ = std::move(other.group_);
  }
  return *this;
}

Series::~Series() { release(); }

void Series::release() noexcept {
  // The file's strong close may already have closed these; HDF5 never reuses an id.
  for (std::int64_t* id : {&step_, &time_, &value_}) {
    if (*id >= 0 && H5Iis_valid(*id) > 0) H5Dclose(*id);
    *id = -1;
  }
  H5Eclear2(H5E_DEFAULT);
}

void Series::append(std::int64_t step, double time, const double* row) {
  auto where = [&] { return "series " + in_file(group_, file_); };
  if (step_ < 0 || H5Iis_valid(step_) <= 0)
    throw Error("cannot append to " + where() + ": the file was committed or closed");
  if (rows_ > 0 && step <= last_step_)
    throw Error("cannot append step " + std::to_string(step) + " to " + where() + " after step " +
                std::to_string(last_step_) + ": steps must increase");
  const hsize_t r = rows_;
  if (!append_row(step_, H5T_NATIVE_INT64, &step, r, 1) ||
      !append_row(time_, H5T_NATIVE_DOUBLE, &time, r, 1) ||
      !append_row(value_, H5T_NATIVE_DOUBLE, row, r, columns_))
    throw Error("cannot append to " + where() + hdf5_reason() + " (disk full?)");
  ++rows_;
  last_step_ = step;
}

void Series::append(std::int64_t step, double time, const std::vector<double>& row) {
  if (row.size() != columns_)
    throw Error("row of " + std::to_string(row.size()) + " values for series " + in_file(group_, file_) +
                ", which has " + std::to_string(columns_) + " columns");
  append(step, time, row.data());
}

SeriesData File::read_series(const std::string& group) const {
  const hid_t file = id(false);
  const std::string g = canonical(group);
  const std::string base = g == "/" ? "" : g;
  SeriesData out;
  out.steps = read_1d<std::int64_t>(file, path_, base + "/step", Want::Int64);
  out.times = read_1d<double>(file, path_, base + "/time", Want::Float);
  const Dataset v = open_dataset(file, path_, base + "/value", Want::Float);
  if (v.dims.size() != 1 && v.dims.size() != 2)
    throw Error("dataset " + in_file(v.path, path_) + " has shape " + shape_text(v.dims) +
                ", expected [rows] or [rows x columns]");
  out.columns = v.dims.size() == 2 ? v.dims[1] : 1;
  out.values = read_whole<double>(v, path_, H5T_NATIVE_DOUBLE);
  const std::size_t rows = v.dims[0];
  if (out.steps.size() != rows || out.times.size() != rows)
    throw Error("series " + in_file(g, path_) + " is inconsistent: " + std::to_string(out.steps.size()) +
                " steps, " + std::to_string(out.times.size()) + " times, " + std::to_string(rows) +
                " value rows");
  return out;
}

}  // namespace granudrag::h5
