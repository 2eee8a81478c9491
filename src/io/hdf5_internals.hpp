#pragma once
// What the h5_*.cpp files share behind h5_file.hpp: HDF5 ids owned RAII-style, error text with
// HDF5's own reason, path handling, and the type checks of the readers. Internal to src/io:
// nothing outside the h5_*.cpp files includes it (it pulls in <hdf5.h>).
#include <hdf5.h>

#include <string>
#include <utility>
#include <vector>

#include "core/error.hpp"

namespace granudrag::h5::detail {

// Below this many elements a dataset is stored contiguous and uncompressed: chunk and filter
// bookkeeping would cost more than it saves.
constexpr hsize_t kCompressFrom = 4096;
// 64 Ki doubles = 512 KiB per chunk: fits the default 1 MiB chunk cache, large enough for
// gzip to work well and for few chunk-index entries.
constexpr hsize_t kChunkElements = 65536;
// Rows per chunk of a Series: one chunk stays in the cache while rows trickle in.
constexpr hsize_t kSeriesChunkRows = 1024;

// HDF5 prints its whole error stack to stderr by default; we report one line instead.
void silence_hdf5();
// The innermost message of HDF5's error stack (the most specific: "truncated file: eof = ...")
// as " (HDF5: ...)". Must be called right after the failing call: any other HDF5 call clears it.
std::string hdf5_reason();

// Owns one HDF5 id and closes it with the matching H5?close.
class Handle {
 public:
  Handle() = default;
  Handle(hid_t id, herr_t (*close)(hid_t)) : id_(id), close_(close) {}
  Handle(Handle&& o) noexcept : id_(std::exchange(o.id_, -1)), close_(o.close_) {}
  Handle& operator=(Handle&& o) noexcept {
    if (this != &o) {
      reset();
      id_ = std::exchange(o.id_, -1);
      close_ = o.close_;
    }
    return *this;
  }
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  ~Handle() { reset(); }
  hid_t get() const { return id_; }
  bool ok() const { return id_ >= 0; }
  hid_t release() { return std::exchange(id_, -1); }

 private:
  void reset() {
    if (id_ >= 0 && close_ != nullptr) close_(id_);
    id_ = -1;
  }
  hid_t id_ = -1;
  herr_t (*close_)(hid_t) = nullptr;
};

std::string in_quotes(const std::string& s);
// "'object' in 'file'", for messages.
std::string in_file(const std::string& object, const std::string& file);
// "/a//b/" -> "/a/b"; "" and "/" -> "/".
std::string canonical(const std::string& path);

// True when a group or dataset exists at `path` (a canonical path).
bool object_exists(hid_t file, const std::string& path);
// What an existing `path` is: H5I_GROUP or H5I_DATASET (H5I_BADID if it cannot be opened).
H5I_type_t kind_of(hid_t file, const std::string& path);
// Creating `path` needs every ancestor that exists to be a group; names the first that is not.
void require_group_ancestors(hid_t file, const std::string& file_name, const std::string& path);
// Link creation that makes missing groups on the way.
Handle link_create_plist();
// Byte shuffle + gzip level 1 on a chunked dataset's creation list, when HDF5 has gzip: level 1
// gets most of the size reduction of level 9 at a fraction of the time per snapshot.
void set_compression(hid_t dcpl);
// HDF5's Fletcher-32 checksum on a chunked dataset's chunks, verified on every read: a flipped
// bit in a file that travelled between file systems is named instead of read as data.
void set_checksum(hid_t dcpl);
// Why a dataset could not be read, to follow "cannot read dataset ... in ...": a failed checksum
// says the file was damaged and to regenerate it; anything else, HDF5's reason.
std::string read_failure();
// Opens the group or dataset at `path`; with `create`, makes a group there (and on the way)
// when nothing exists yet.
Handle open_object(hid_t file, const std::string& file_name, const std::string& path, bool create);

// Readers and the types they accept: only conversions HDF5 makes without loss.
enum class Want { Float, Int64, Int, UInt8 };
bool accepts(Want want, hid_t type);
const char* wanted(Want want);                             // "floating-point numbers", ...
hid_t memory_type(Want want);                              // H5T_NATIVE_DOUBLE, ...
std::string describe(hid_t type);                          // "64-bit floats", "strings", ...
std::string shape_text(const std::vector<hsize_t>& dims);  // "a scalar", "[3 x 2]"

// An open dataset whose type a reader accepts, with its shape.
struct Dataset {
  Handle dset;
  std::vector<hsize_t> dims;
  std::size_t count = 0;
  std::string path;
};
Dataset open_dataset(hid_t file, const std::string& file_name, const std::string& raw_path, Want want);
void require_shape(const Dataset& d, const std::string& file_name, std::size_t rank, std::size_t columns,
                   const char* expected);

template <class T>
std::vector<T> read_whole(const Dataset& d, const std::string& file_name, hid_t mem_type) {
  std::vector<T> out(d.count);
  if (d.count > 0 && H5Dread(d.dset.get(), mem_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.data()) < 0)
    throw Error("cannot read dataset " + in_file(d.path, file_name) + read_failure());
  return out;
}

template <class T>
std::vector<T> read_1d(hid_t file, const std::string& file_name, const std::string& path, Want want) {
  const Dataset d = open_dataset(file, file_name, path, want);
  require_shape(d, file_name, 1, 0, "a 1-D array [N]");
  return read_whole<T>(d, file_name, memory_type(want));
}

}  // namespace granudrag::h5::detail
