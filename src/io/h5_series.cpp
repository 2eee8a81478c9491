// Series: H5MD time-dependent elements written one row at a time, and read back whole.
#include "io/h5_file.hpp"

#include <hdf5.h>

#include <algorithm>

#include "core/error.hpp"
#include "io/hdf5_internals.hpp"

namespace granudrag::h5 {

using namespace detail;

namespace {

// An extendible dataset of rows shaped `row` (empty: scalar rows), chunked by whole rows while
// a row fits in a chunk, else a row is split along its first dimension.
Handle create_extendible(hid_t file, const std::string& file_name, const std::string& path, hid_t file_type,
                         const std::vector<hsize_t>& row) {
  std::vector<hsize_t> dims{0}, max_dims{H5S_UNLIMITED}, chunk{1};
  hsize_t per_row = 1;
  for (hsize_t n : row) {
    dims.push_back(n);
    max_dims.push_back(n);
    chunk.push_back(n);
    per_row *= n;
  }
  if (per_row <= kChunkElements) {
    chunk[0] = std::max<hsize_t>(1, std::min<hsize_t>(kSeriesChunkRows, kChunkElements / per_row));
  } else {
    const hsize_t rest = per_row / row[0];
    chunk[1] = std::max<hsize_t>(1, kChunkElements / rest);
  }
  const int rank = static_cast<int>(dims.size());
  const Handle space(H5Screate_simple(rank, dims.data(), max_dims.data()), H5Sclose);
  const Handle dcpl(H5Pcreate(H5P_DATASET_CREATE), H5Pclose);
  H5Pset_chunk(dcpl.get(), rank, chunk.data());
  set_compression(dcpl.get());
  set_checksum(dcpl.get());
  const Handle lcpl = link_create_plist();
  Handle dset(H5Dcreate2(file, path.c_str(), file_type, space.get(), lcpl.get(), dcpl.get(), H5P_DEFAULT),
              H5Dclose);
  if (!dset.ok()) throw Error("cannot create dataset " + in_file(path, file_name) + hdf5_reason());
  return dset;
}

// Grows `dset` to `row + 1` rows and writes one row, shaped `shape`, into the new row.
bool append_row(hid_t dset, hid_t mem_type, const void* data, hsize_t row,
                const std::vector<hsize_t>& shape) {
  std::vector<hsize_t> dims{row + 1}, start{row}, count{1};
  hsize_t elements = 1;
  for (hsize_t n : shape) {
    dims.push_back(n);
    start.push_back(0);
    count.push_back(n);
    elements *= n;
  }
  if (H5Dset_extent(dset, dims.data()) < 0) return false;
  const Handle file_space(H5Dget_space(dset), H5Sclose);
  if (H5Sselect_hyperslab(file_space.get(), H5S_SELECT_SET, start.data(), nullptr, count.data(), nullptr) < 0)
    return false;
  const Handle mem_space(H5Screate_simple(1, &elements, nullptr), H5Sclose);
  return H5Dwrite(dset, mem_type, mem_space.get(), file_space.get(), H5P_DEFAULT, data) >= 0;
}

}  // namespace

Series File::series(const std::string& group, std::size_t columns) {
  if (columns == 0) throw Error("series " + in_file(canonical(group), path_) + " needs at least one column");
  return series(group, columns > 1 ? std::vector<std::size_t>{columns} : std::vector<std::size_t>{});
}

Series File::series(const std::string& group, const std::vector<std::size_t>& row_shape) {
  const hid_t file = id(true);
  const std::string g = canonical(group);
  std::size_t columns = 1;
  for (std::size_t n : row_shape) columns *= n;
  if (columns == 0) throw Error("series " + in_file(g, path_) + " has an empty row shape");
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
  s.row_shape_.assign(row_shape.begin(), row_shape.end());
  s.step_ = create_extendible(file, path_, base + "/step", H5T_STD_I64LE, {}).release();
  s.time_ = create_extendible(file, path_, base + "/time", H5T_IEEE_F64LE, {}).release();
  s.value_ = create_extendible(file, path_, base + "/value", H5T_IEEE_F64LE,
                               std::vector<hsize_t>(row_shape.begin(), row_shape.end()))
                 .release();
  return s;
}

Series::Series(Series&& other) noexcept
    : step_(std::exchange(other.step_, -1)),
      time_(std::exchange(other.time_, -1)),
      value_(std::exchange(other.value_, -1)),
      columns_(other.columns_),
      row_shape_(std::move(other.row_shape_)),
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
    row_shape_ = std::move(other.row_shape_);
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
  if (!append_row(step_, H5T_NATIVE_INT64, &step, r, {}) ||
      !append_row(time_, H5T_NATIVE_DOUBLE, &time, r, {}) ||
      !append_row(value_, H5T_NATIVE_DOUBLE, row, r,
                  std::vector<hsize_t>(row_shape_.begin(), row_shape_.end())))
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
  if (v.dims.empty())
    throw Error("dataset " + in_file(v.path, path_) + " has shape " + shape_text(v.dims) +
                ", expected [rows] or [rows x ...]");
  out.row_shape.assign(v.dims.begin() + 1, v.dims.end());
  out.columns = 1;
  for (std::size_t n : out.row_shape) out.columns *= n;
  out.values = read_whole<double>(v, path_, H5T_NATIVE_DOUBLE);
  const std::size_t rows = v.dims[0];
  if (out.steps.size() != rows || out.times.size() != rows)
    throw Error("series " + in_file(g, path_) + " is inconsistent: " + std::to_string(out.steps.size()) +
                " steps, " + std::to_string(out.times.size()) + " times, " + std::to_string(rows) +
                " value rows");
  return out;
}

}  // namespace granudrag::h5
