#pragma once
// Run files (beds, pulls, checkpoints): HDF5 laid out after H5MD 1.1
// (https://www.nongnu.org/h5md/h5md.html), through a small RAII layer over the HDF5 C API.
//
// A file is written once, from a fresh start, and appears under its name only when complete:
// File::create() writes `path.tmp` and commit() renames it, so a crash, a full disk or an
// exception leaves either the previous file or none, never half of one. Every HDF5 failure
// becomes a granudrag::Error naming the file and the object; HDF5's own stack dump is silenced.
//
// Paths are slash paths from the root ("/particles/all/position/value"); missing groups on the
// way are created. Each dataset is written whole, once. Readers check rank, shape and type
// and refuse anything that would convert with loss (a float read as an integer, say).
//
// Debian's HDF5 is the serial, non-thread-safe build: use these classes from one thread.
#include <cstdint>
#include <limits>
#include <string>
#include <type_traits>
#include <vector>

#include "core/vec3.hpp"

namespace granudrag::h5 {

// A time series read back whole: row i was sampled at steps[i] and times[i], and its values
// are values[i * columns] ... values[i * columns + columns - 1].
struct SeriesData {
  std::vector<std::int64_t> steps;
  std::vector<double> times;
  std::vector<double> values;
  std::size_t columns = 1;             // values per row: the product of row_shape
  std::vector<std::size_t> row_shape;  // empty for scalar rows; {N, 3} for frames of N vectors
  std::size_t rows() const { return steps.size(); }
};

// An H5MD time-dependent element being written: <group>/step (int64), <group>/time (double)
// and <group>/value (double, rows x columns, or 1-D when columns == 1), all extendible and
// chunked, so that one row at a time is cheap. Obtained from File::series(); writes go straight
// to the file's chunk cache, nothing is buffered here. Valid until its file is committed or
// closed; appending after that is an Error.
class Series {
 public:
  Series(Series&& other) noexcept;
  Series& operator=(Series&& other) noexcept;
  Series(const Series&) = delete;
  Series& operator=(const Series&) = delete;
  ~Series();

  // Reads columns() doubles from `row`. Steps must increase strictly (H5MD).
  void append(std::int64_t step, double time, const double* row);
  // The same, checking that row.size() == columns().
  void append(std::int64_t step, double time, const std::vector<double>& row);

  std::size_t columns() const { return columns_; }
  std::size_t rows() const { return rows_; }
  const std::string& group() const { return group_; }

 private:
  friend class File;
  Series() = default;
  void release() noexcept;

  // HDF5 ids (hid_t is int64_t in HDF5 >= 1.10; checked in the .cpp): no <hdf5.h> here.
  std::int64_t step_ = -1, time_ = -1, value_ = -1;
  std::size_t columns_ = 0;
  std::vector<std::size_t> row_shape_;
  std::size_t rows_ = 0;
  std::int64_t last_step_ = 0;
  std::string file_, group_;
};

// Whether a File's large datasets are compressed. Checkpoints are not: they live minutes, and
// gzip took two thirds of a pull's checkpoint time (0.18 of 0.27 s over 10 checkpoints of a
// 7.7k-body pull).
enum class Compression { Gzip, None };

class File {
 public:
  // Creates (truncating) `path + ".tmp"`; nothing appears at `path` until commit().
  static File create(const std::string& path, Compression compression = Compression::Gzip);
  // Opens an existing file read-only. A missing, non-HDF5, truncated or corrupt file is an
  // Error saying which and naming the file.
  static File open(const std::string& path);

  File(File&& other) noexcept;
  File& operator=(File&& other) noexcept;
  File(const File&) = delete;
  File& operator=(const File&) = delete;
  // A file created for writing and never committed is closed and its .tmp removed.
  ~File();

  // Flushes, closes, syncs to disk and renames `path.tmp` to `path`, replacing any file
  // there. The File is closed afterwards; so are Series obtained from it.
  void commit();

  const std::string& path() const { return path_; }
  bool writable() const { return writable_; }
  // True when a group or dataset exists at `path` ("/" always does).
  bool exists(const std::string& path) const;
  // Makes a group at `path` (and groups on the way) unless one is there already.
  void create_group(const std::string& path);

  // Whole 1-D datasets. Arrays of 4096 elements or more are chunked and, unless the file was
  // created with Compression::None, compressed (shuffle + gzip level 1: most of the gain for
  // little time).
  void write(const std::string& path, const std::vector<double>& data);
  void write(const std::string& path, const std::vector<std::int64_t>& data);
  void write(const std::string& path, const std::vector<int>& data);
  void write(const std::string& path, const std::vector<std::uint8_t>& data);
  // N x 3 doubles, one row per vector.
  void write_rows(const std::string& path, const std::vector<Vec3>& rows);

  std::vector<double> read_doubles(const std::string& path) const;
  std::vector<std::int64_t> read_int64(const std::string& path) const;
  std::vector<int> read_ints(const std::string& path) const;
  std::vector<std::uint8_t> read_uint8(const std::string& path) const;
  std::vector<Vec3> read_vec3(const std::string& path) const;

  // Attributes on a group or dataset; setting one on a path that does not exist yet creates
  // a group there. Setting an existing attribute replaces it. Strings are stored as
  // fixed-length, as H5MD asks of its metadata.
  void set_attr(const std::string& path, const std::string& name, double value);
  void set_attr(const std::string& path, const std::string& name, std::int64_t value);
  void set_attr(const std::string& path, const std::string& name, const std::string& value);
  void set_attr(const std::string& path, const std::string& name, const std::vector<std::int64_t>& values);
  void set_attr(const std::string& path, const std::string& name, const std::vector<std::string>& values);
  void set_attr(const std::string& path, const std::string& name, const std::vector<double>& values);
  // A flag, stored as h5py stores a numpy bool (which it reads back as one): an 8-bit enum
  // {FALSE = 0, TRUE = 1}. Not an overload of set_attr: a string literal would convert to bool.
  void set_flag_attr(const std::string& path, const std::string& name, bool value);
  // Any other integer (int, std::size_t, ...) is stored as int64, so that
  // set_attr(p, "count", v.size()) compiles without a cast. bool is refused at compile time.
  template <class T, std::enable_if_t<std::is_integral_v<T> && !std::is_same_v<T, bool> &&
                                          !std::is_same_v<T, std::int64_t>,
                                      int> = 0>
  void set_attr(const std::string& path, const std::string& name, T value) {
    if constexpr (std::is_unsigned_v<T> && sizeof(T) >= sizeof(std::int64_t))
      if (value > static_cast<T>(std::numeric_limits<std::int64_t>::max())) attr_overflow(path, name);
    set_attr(path, name, static_cast<std::int64_t>(value));
  }

  bool has_attr(const std::string& path, const std::string& name) const;
  double get_attr_double(const std::string& path, const std::string& name) const;
  std::int64_t get_attr_int64(const std::string& path, const std::string& name) const;
  std::string get_attr_string(const std::string& path, const std::string& name) const;
  std::vector<std::int64_t> get_attr_int64s(const std::string& path, const std::string& name) const;
  std::vector<std::string> get_attr_strings(const std::string& path, const std::string& name) const;
  std::vector<double> get_attr_doubles(const std::string& path, const std::string& name) const;
  bool get_attr_flag(const std::string& path, const std::string& name) const;

  // For attributes whose type is not known in advance (a record of parameters, say): the names
  // on a group or dataset (in name order), and what one holds.
  enum class AttrType { Float, Integer, String, Flag, Other };
  struct AttrShape {
    AttrType type = AttrType::Other;
    bool scalar = true;     // a scalar, or else a 1-D (or larger) array
    std::size_t count = 1;  // number of elements
  };
  std::vector<std::string> attr_names(const std::string& path) const;
  AttrShape attr_shape(const std::string& path, const std::string& name) const;

  // Starts an H5MD time-dependent element at `group` (e.g. "/observables/drag"); see Series.
  Series series(const std::string& group, std::size_t columns);
  // The same with rows of any shape: value is [rows x row_shape...], e.g. frames of N particle
  // positions as [frames x N x 3] (H5MD's leading time dimension); append() takes the row's
  // values in C order.
  Series series(const std::string& group, const std::vector<std::size_t>& row_shape);
  SeriesData read_series(const std::string& group) const;

 private:
  File() = default;
  void close_quietly() noexcept;
  std::int64_t id(bool for_writing) const;  // the open HDF5 file, or an Error saying why not
  [[noreturn]] void attr_overflow(const std::string& path, const std::string& name) const;

  std::int64_t id_ = -1;  // hid_t
  std::string path_;      // the final name; while writing, the data is in path_ + ".tmp"
  bool writable_ = false;
  bool committed_ = false;
  Compression compression_ = Compression::Gzip;
};

// The mandatory /h5md group of H5MD 1.1: attribute version = [1, 1]; /h5md/author with the
// author's name (empty: the login name, else "unknown"); /h5md/creator with name "granudrag"
// and the given version.
void write_h5md_header(File& file, const std::string& creator_version, const std::string& author = "");

}  // namespace granudrag::h5
