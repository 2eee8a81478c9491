#include "io/h5_file.hpp"

#include <fcntl.h>
#include <hdf5.h>
#include <pwd.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <mutex>
#include <utility>

#include "core/error.hpp"

namespace granudrag::h5 {

static_assert(std::is_same_v<hid_t, std::int64_t>,
              "h5_file.hpp stores HDF5 ids as std::int64_t, which needs HDF5 >= 1.10");
static_assert(sizeof(Vec3) == 3 * sizeof(double),
              "std::vector<Vec3> is read and written as one N x 3 block of doubles");
static_assert(sizeof(int) == 4, "int datasets are stored as 32-bit integers");

namespace fs = std::filesystem;

namespace {

// Below this many elements a dataset is stored contiguous and uncompressed: chunk and filter
// bookkeeping would cost more than it saves.
constexpr hsize_t kCompressFrom = 4096;
// 64 Ki doubles = 512 KiB per chunk: fits the default 1 MiB chunk cache, large enough for
// gzip to work well and for few chunk-index entries.
constexpr hsize_t kChunkElements = 65536;
// Rows per chunk of a Series: one chunk stays in the cache while rows trickle in.
constexpr hsize_t kSeriesChunkRows = 1024;

// HDF5 prints its whole error stack to stderr by default; we report one line instead.
void silence_hdf5() {
  static std::once_flag once;
  std::call_once(once, [] { H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr); });
}

herr_t keep_deepest(unsigned, const H5E_error2_t* e, void* out) {
  if (e->desc != nullptr && e->desc[0] != '\0') *static_cast<std::string*>(out) = e->desc;
  return 0;
}

// The innermost message of HDF5's error stack (the most specific: "truncated file: eof = ...")
// as " (HDF5: ...)". Must be called right after the failing call: any other HDF5 call clears it.
std::string hdf5_reason() {
  std::string reason;
  H5Ewalk2(H5E_DEFAULT, H5E_WALK_DOWNWARD, keep_deepest, &reason);
  H5Eclear2(H5E_DEFAULT);
  return reason.empty() ? std::string() : " (HDF5: " + reason + ")";
}

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

std::string in_quotes(const std::string& s) { return "'" + s + "'"; }

// "/a//b/" -> "/a/b"; "" and "/" -> "/".
std::string canonical(const std::string& path) {
  std::string out;
  std::size_t i = 0;
  while (i < path.size()) {
    while (i < path.size() && path[i] == '/') ++i;
    const std::size_t j = path.find('/', i);
    const std::size_t end = j == std::string::npos ? path.size() : j;
    if (end > i) out += "/" + path.substr(i, end - i);
    i = end;
  }
  return out.empty() ? "/" : out;
}

std::string in_file(const std::string& object, const std::string& file) {
  return in_quotes(object) + " in " + in_quotes(file);
}

// H5Lexists fails rather than answering "no" when a group on the way is missing or is a
// dataset, so the path is checked one link at a time.
bool object_exists(hid_t file, const std::string& path) {
  if (path == "/") return true;
  std::size_t pos = 0;
  while (true) {
    pos = path.find('/', pos + 1);
    const std::string prefix = path.substr(0, pos);
    if (H5Lexists(file, prefix.c_str(), H5P_DEFAULT) <= 0) {
      H5Eclear2(H5E_DEFAULT);
      return false;
    }
    if (pos == std::string::npos) break;
  }
  const htri_t ok = H5Oexists_by_name(file, path.c_str(), H5P_DEFAULT);  // not a dangling link
  H5Eclear2(H5E_DEFAULT);
  return ok > 0;
}

// What an existing `path` is: H5I_GROUP or H5I_DATASET (H5I_BADID if it cannot be opened).
H5I_type_t kind_of(hid_t file, const std::string& path) {
  const hid_t object = H5Oopen(file, path.c_str(), H5P_DEFAULT);
  const H5I_type_t kind = object >= 0 ? H5Iget_type(object) : H5I_BADID;
  if (object >= 0) H5Oclose(object);
  H5Eclear2(H5E_DEFAULT);
  return kind;
}

// Creating `path` needs every ancestor that exists to be a group; names the first that is not.
void require_group_ancestors(hid_t file, const std::string& file_name, const std::string& path) {
  for (std::size_t pos = path.find('/', 1); pos != std::string::npos; pos = path.find('/', pos + 1)) {
    const std::string ancestor = path.substr(0, pos);
    if (!object_exists(file, ancestor)) return;
    if (kind_of(file, ancestor) != H5I_GROUP)
      throw Error("cannot create " + in_file(path, file_name) + ": " + in_quotes(ancestor) +
                  " is a dataset, not a group");
  }
}

Handle link_create_plist() {
  Handle lcpl(H5Pcreate(H5P_LINK_CREATE), H5Pclose);
  H5Pset_create_intermediate_group(lcpl.get(), 1);
  return lcpl;
}

// Opens the group or dataset at `path`; with `create`, makes a group there (and on the way)
// when nothing exists yet.
Handle open_object(hid_t file, const std::string& file_name, const std::string& path, bool create) {
  if (!object_exists(file, path)) {
    if (!create) throw Error("no group or dataset " + in_file(path, file_name));
    require_group_ancestors(file, file_name, path);
    const Handle lcpl = link_create_plist();
    Handle group(H5Gcreate2(file, path.c_str(), lcpl.get(), H5P_DEFAULT, H5P_DEFAULT), H5Gclose);
    if (!group.ok()) throw Error("cannot create group " + in_file(path, file_name) + hdf5_reason());
    return group;
  }
  Handle object(H5Oopen(file, path.c_str(), H5P_DEFAULT), H5Oclose);
  if (!object.ok()) throw Error("cannot open " + in_file(path, file_name) + hdf5_reason());
  return object;
}

// Readers and the types they accept: only conversions HDF5 makes without loss.
enum class Want { Float, Int64, Int, UInt8 };

bool accepts(Want want, hid_t type) {
  const H5T_class_t cls = H5Tget_class(type);
  const std::size_t size = H5Tget_size(type);
  if (want == Want::Float) return cls == H5T_FLOAT;
  if (cls != H5T_INTEGER) return false;
  const bool is_signed = H5Tget_sign(type) == H5T_SGN_2;
  switch (want) {
    case Want::Int64:
      return is_signed ? size <= 8 : size < 8;
    case Want::Int:
      return is_signed ? size <= 4 : size < 4;
    case Want::UInt8:
      return !is_signed && size == 1;
    default:
      return false;
  }
}

const char* wanted(Want want) {
  switch (want) {
    case Want::Float:
      return "floating-point numbers";
    case Want::Int64:
      return "integers that fit in 64-bit signed integers";
    case Want::Int:
      return "integers that fit in 32-bit signed integers";
    case Want::UInt8:
      return "8-bit unsigned integers";
  }
  return "";
}

std::string describe(hid_t type) {
  const std::string bits = std::to_string(8 * H5Tget_size(type)) + "-bit ";
  switch (H5Tget_class(type)) {
    case H5T_FLOAT:
      return bits + "floats";
    case H5T_INTEGER:
      return bits + (H5Tget_sign(type) == H5T_SGN_2 ? "signed" : "unsigned") + " integers";
    case H5T_STRING:
      return "strings";
    case H5T_COMPOUND:
      return "compound records";
    case H5T_ENUM:
      return "enumerations";
    default:
      return "data of HDF5 type class " + std::to_string(H5Tget_class(type));
  }
}

std::string shape_text(const std::vector<hsize_t>& dims) {
  if (dims.empty()) return "a scalar";
  std::string s = "[";
  for (std::size_t k = 0; k < dims.size(); ++k) s += (k ? " x " : "") + std::to_string(dims[k]);
  return s + "]";
}

hid_t memory_type(Want want) {
  switch (want) {
    case Want::Float:
      return H5T_NATIVE_DOUBLE;
    case Want::Int64:
      return H5T_NATIVE_INT64;
    case Want::Int:
      return H5T_NATIVE_INT;
    case Want::UInt8:
      return H5T_NATIVE_UINT8;
  }
  return -1;
}

// ---- datasets

void create_and_write(hid_t file, const std::string& file_name, const std::string& raw_path, hid_t file_type,
                      hid_t mem_type, const std::vector<hsize_t>& dims, const void* data) {
  const std::string path = canonical(raw_path);
  if (path == "/") throw Error("cannot write a dataset at the root of " + in_quotes(file_name));
  if (object_exists(file, path))
    throw Error(in_file(path, file_name) + " already exists: each dataset is written once");
  require_group_ancestors(file, file_name, path);
  hsize_t total = 1;
  for (hsize_t d : dims) total *= d;

  Handle space(H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr), H5Sclose);
  Handle dcpl(H5Pcreate(H5P_DATASET_CREATE), H5Pclose);
  if (total >= kCompressFrom) {
    std::vector<hsize_t> chunk = dims;
    const hsize_t row = total / dims[0];
    chunk[0] = std::max<hsize_t>(1, std::min<hsize_t>(dims[0], kChunkElements / row));
    H5Pset_chunk(dcpl.get(), static_cast<int>(chunk.size()), chunk.data());
    if (H5Zfilter_avail(H5Z_FILTER_DEFLATE) > 0) {
      H5Pset_shuffle(dcpl.get());
      H5Pset_deflate(dcpl.get(), 1);
    }
  }
  const Handle lcpl = link_create_plist();
  Handle dset(H5Dcreate2(file, path.c_str(), file_type, space.get(), lcpl.get(), dcpl.get(), H5P_DEFAULT),
              H5Dclose);
  if (!dset.ok()) throw Error("cannot create dataset " + in_file(path, file_name) + hdf5_reason());
  if (total > 0 && H5Dwrite(dset.get(), mem_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) < 0)
    throw Error("cannot write dataset " + in_file(path, file_name) + hdf5_reason() + " (disk full?)");
}

struct Dataset {
  Handle dset;
  std::vector<hsize_t> dims;
  std::size_t count = 0;
  std::string path;
};

Dataset open_dataset(hid_t file, const std::string& file_name, const std::string& raw_path, Want want) {
  Dataset d;
  d.path = canonical(raw_path);
  if (!object_exists(file, d.path)) throw Error("no dataset " + in_file(d.path, file_name));
  if (kind_of(file, d.path) == H5I_GROUP)
    throw Error(in_file(d.path, file_name) + " is a group, not a dataset");
  d.dset = Handle(H5Dopen2(file, d.path.c_str(), H5P_DEFAULT), H5Dclose);
  if (!d.dset.ok()) throw Error("cannot open dataset " + in_file(d.path, file_name) + hdf5_reason());
  const Handle type(H5Dget_type(d.dset.get()), H5Tclose);
  if (!accepts(want, type.get()))
    throw Error("dataset " + in_file(d.path, file_name) + " holds " + describe(type.get()) + ", not " +
                wanted(want));
  const Handle space(H5Dget_space(d.dset.get()), H5Sclose);
  const int rank = H5Sget_simple_extent_ndims(space.get());
  if (rank < 0) throw Error("cannot read the shape of " + in_file(d.path, file_name) + hdf5_reason());
  d.dims.resize(static_cast<std::size_t>(rank));
  H5Sget_simple_extent_dims(space.get(), d.dims.data(), nullptr);
  d.count = static_cast<std::size_t>(H5Sget_simple_extent_npoints(space.get()));
  return d;
}

void require_shape(const Dataset& d, const std::string& file_name, std::size_t rank, std::size_t columns,
                   const char* expected) {
  const bool ok = d.dims.size() == rank && (rank < 2 || d.dims[1] == columns);
  if (!ok)
    throw Error("dataset " + in_file(d.path, file_name) + " has shape " + shape_text(d.dims) + ", expected " +
                expected);
}

template <class T>
std::vector<T> read_whole(const Dataset& d, const std::string& file_name, hid_t mem_type) {
  std::vector<T> out(d.count);
  if (d.count > 0 && H5Dread(d.dset.get(), mem_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.data()) < 0)
    throw Error("cannot read dataset " + in_file(d.path, file_name) + hdf5_reason() +
                "; the file may be damaged");
  return out;
}

template <class T>
std::vector<T> read_1d(hid_t file, const std::string& file_name, const std::string& path, Want want) {
  const Dataset d = open_dataset(file, file_name, path, want);
  require_shape(d, file_name, 1, 0, "a 1-D array [N]");
  return read_whole<T>(d, file_name, memory_type(want));
}

// ---- attributes

std::string attr_where(const std::string& name, const std::string& path, const std::string& file) {
  return "attribute " + in_quotes(name) + " on " + in_file(path, file);
}

void write_attr(hid_t file, const std::string& file_name, const std::string& raw_path,
                const std::string& name, hid_t file_type, hid_t mem_type, hid_t space, const void* data) {
  const std::string path = canonical(raw_path);
  if (name.empty()) throw Error("empty attribute name for " + in_file(path, file_name));
  const Handle object = open_object(file, file_name, path, true);
  if (H5Aexists(object.get(), name.c_str()) > 0 && H5Adelete(object.get(), name.c_str()) < 0)
    throw Error("cannot replace " + attr_where(name, path, file_name) + hdf5_reason());
  Handle attr(H5Acreate2(object.get(), name.c_str(), file_type, space, H5P_DEFAULT, H5P_DEFAULT), H5Aclose);
  if (!attr.ok() || H5Awrite(attr.get(), mem_type, data) < 0)
    throw Error("cannot write " + attr_where(name, path, file_name) + hdf5_reason());
}

// A fixed-length string type wide enough for `width` bytes plus the terminating NUL.
Handle fixed_string_type(std::size_t width, bool utf8) {
  Handle type(H5Tcopy(H5T_C_S1), H5Tclose);
  H5Tset_size(type.get(), width + 1);
  H5Tset_strpad(type.get(), H5T_STR_NULLTERM);
  H5Tset_cset(type.get(), utf8 ? H5T_CSET_UTF8 : H5T_CSET_ASCII);
  return type;
}

bool any_non_ascii(const std::vector<std::string>& values) {
  for (const auto& v : values)
    for (unsigned char c : v)
      if (c >= 0x80) return true;
  return false;
}

void write_string_attr(hid_t file, const std::string& file_name, const std::string& path,
                       const std::string& name, const std::vector<std::string>& values, bool scalar) {
  std::size_t width = 0;
  for (const auto& v : values) width = std::max(width, v.size());
  const Handle type = fixed_string_type(width, any_non_ascii(values));
  std::vector<char> buffer(values.size() * (width + 1), '\0');
  for (std::size_t k = 0; k < values.size(); ++k)
    std::copy(values[k].begin(), values[k].end(), buffer.begin() + k * (width + 1));
  const hsize_t n = values.size();
  const Handle space(scalar ? H5Screate(H5S_SCALAR) : H5Screate_simple(1, &n, nullptr), H5Sclose);
  write_attr(file, file_name, path, name, type.get(), type.get(), space.get(), buffer.data());
}

struct Attribute {
  Handle attr, type;
  std::size_t count = 0;
  std::string where;
};

Attribute open_attr(hid_t file, const std::string& file_name, const std::string& raw_path,
                    const std::string& name) {
  const std::string path = canonical(raw_path);
  Attribute a;
  a.where = attr_where(name, path, file_name);
  const Handle object = open_object(file, file_name, path, false);
  if (H5Aexists(object.get(), name.c_str()) <= 0) {
    H5Eclear2(H5E_DEFAULT);
    throw Error("no " + a.where);
  }
  a.attr = Handle(H5Aopen(object.get(), name.c_str(), H5P_DEFAULT), H5Aclose);
  if (!a.attr.ok()) throw Error("cannot open " + a.where + hdf5_reason());
  a.type = Handle(H5Aget_type(a.attr.get()), H5Tclose);
  const Handle space(H5Aget_space(a.attr.get()), H5Sclose);
  const hssize_t n = H5Sget_simple_extent_npoints(space.get());
  if (n < 0) throw Error("cannot read the shape of " + a.where + hdf5_reason());
  a.count = static_cast<std::size_t>(n);
  return a;
}

template <class T>
std::vector<T> read_numeric_attr(const Attribute& a, Want want) {
  if (!accepts(want, a.type.get()))
    throw Error(a.where + " holds " + describe(a.type.get()) + ", not " + wanted(want));
  std::vector<T> out(a.count);
  if (a.count > 0 && H5Aread(a.attr.get(), memory_type(want), out.data()) < 0)
    throw Error("cannot read " + a.where + hdf5_reason());
  return out;
}

std::vector<std::string> read_string_attr(const Attribute& a) {
  if (H5Tget_class(a.type.get()) != H5T_STRING)
    throw Error(a.where + " holds " + describe(a.type.get()) + ", not strings");
  std::vector<std::string> out;
  out.reserve(a.count);
  if (H5Tis_variable_str(a.type.get()) > 0) {  // as h5py writes str attributes
    Handle mem(H5Tcopy(H5T_C_S1), H5Tclose);
    H5Tset_size(mem.get(), H5T_VARIABLE);
    H5Tset_cset(mem.get(), H5Tget_cset(a.type.get()));
    std::vector<char*> ptrs(a.count, nullptr);
    if (a.count > 0 && H5Aread(a.attr.get(), mem.get(), ptrs.data()) < 0)
      throw Error("cannot read " + a.where + hdf5_reason());
    for (char* p : ptrs) {
      out.emplace_back(p != nullptr ? p : "");
      if (p != nullptr) H5free_memory(p);
    }
    return out;
  }
  const std::size_t width = H5Tget_size(a.type.get());
  std::vector<char> buffer(a.count * width);
  if (a.count > 0 && H5Aread(a.attr.get(), a.type.get(), buffer.data()) < 0)
    throw Error("cannot read " + a.where + hdf5_reason());
  const bool space_padded = H5Tget_strpad(a.type.get()) == H5T_STR_SPACEPAD;
  for (std::size_t k = 0; k < a.count; ++k) {
    const char* begin = buffer.data() + k * width;
    std::string s(begin, std::find(begin, begin + width, '\0'));
    if (space_padded) s.erase(s.find_last_not_of(' ') + 1);
    out.push_back(std::move(s));
  }
  return out;
}

template <class T>
T only_value(const std::vector<T>& values, const std::string& where, const char* plural_getter) {
  if (values.size() != 1)
    throw Error(where + " holds " + std::to_string(values.size()) + " values, not one" +
                (plural_getter[0] ? std::string("; read it with ") + plural_getter : std::string()));
  return values.front();
}

// ---- files

Handle file_access_plist() {
  Handle fapl(H5Pcreate(H5P_FILE_ACCESS), H5Pclose);
  // Closing the file closes every object still open in it (a Series, say), so that the file
  // is really closed, and complete on disk, before commit() renames it.
  H5Pset_fclose_degree(fapl.get(), H5F_CLOSE_STRONG);
  // The 1.8 format (superblock v2, as H5MD recommends): readable by every HDF5 since 1.8.
  H5Pset_libver_bounds(fapl.get(), H5F_LIBVER_V18, H5F_LIBVER_V18);
#if H5_VERSION_GE(1, 10, 7)
  // Cluster file systems without flock() would otherwise make every open fail.
  H5Pset_file_locking(fapl.get(), 1, 1);
#endif
  return fapl;
}

void fsync_path(const std::string& path, int flags) {
  const int fd = ::open(path.c_str(), flags);
  if (fd < 0) return;  // best effort: durability, not correctness, depends on it
  ::fsync(fd);
  ::close(fd);
}

std::string login_name() {
  if (const char* user = std::getenv("USER"); user != nullptr && user[0] != '\0') return user;
  if (const passwd* pw = getpwuid(geteuid()); pw != nullptr && pw->pw_name != nullptr) return pw->pw_name;
  return "unknown";
}

}  // namespace

// ================================================================ File

File File::create(const std::string& path) {
  silence_hdf5();
  if (path.empty()) throw Error("no output file name given");
  const std::string tmp = path + ".tmp";
  const fs::path dir = fs::path(path).parent_path();
  std::error_code ec;
  if (!dir.empty() && !fs::is_directory(dir, ec))
    throw Error("cannot create " + in_quotes(path) + ": directory " + in_quotes(dir.string()) +
                " does not exist");
  if (fs::is_directory(path, ec)) throw Error("cannot create " + in_quotes(path) + ": it is a directory");
  const Handle fapl = file_access_plist();
  const hid_t id = H5Fcreate(tmp.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, fapl.get());
  if (id < 0)
    throw Error("cannot create " + in_quotes(tmp) + hdf5_reason() +
                ": check that its directory is writable and that no other run is writing it");
  File f;
  f.id_ = id;
  f.path_ = path;
  f.writable_ = true;
  return f;
}

File File::open(const std::string& path) {
  silence_hdf5();
  std::error_code ec;
  if (!fs::exists(path, ec)) throw Error("cannot open " + in_quotes(path) + ": no such file");
  if (fs::is_directory(path, ec)) throw Error("cannot open " + in_quotes(path) + ": it is a directory");
  const htri_t is_hdf5 = H5Fis_hdf5(path.c_str());
  if (is_hdf5 < 0) throw Error("cannot read " + in_quotes(path) + hdf5_reason() + ": check its permissions");
  if (is_hdf5 == 0)
    throw Error(in_quotes(path) +
                " is not an HDF5 file (no HDF5 signature): was it written by "
                "granudrag, and completely?");
  const Handle fapl = file_access_plist();
  const hid_t id = H5Fopen(path.c_str(), H5F_ACC_RDONLY, fapl.get());
  if (id < 0)
    throw Error(in_quotes(path) +
                " is an HDF5 file but cannot be opened: it is truncated or "
                "corrupt" +
                hdf5_reason() + "; regenerate it");
  File f;
  f.id_ = id;
  f.path_ = path;
  return f;
}

File::File(File&& other) noexcept
    : id_(std::exchange(other.id_, -1)),
      path_(std::move(other.path_)),
      writable_(std::exchange(other.writable_, false)),
      committed_(other.committed_) {}

File& File::operator=(File&& other) noexcept {
  if (this != &other) {
    close_quietly();
    id_ = std::exchange(other.id_, -1);
    path_ = std::move(other.path_);
    writable_ = std::exchange(other.writable_, false);
    committed_ = other.committed_;
  }
  return *this;
}

File::~File() { close_quietly(); }

void File::close_quietly() noexcept {
  if (id_ >= 0) H5Fclose(id_);
  id_ = -1;
  if (writable_ && !committed_) {
    std::error_code ec;
    fs::remove(path_ + ".tmp", ec);
  }
  writable_ = false;
}

std::int64_t File::id(bool for_writing) const {
  if (id_ < 0)
    throw Error(in_quotes(path_) + (committed_ ? " was committed and is closed" : " is not open") +
                "; open it again to read it");
  if (for_writing && !writable_)
    throw Error(in_quotes(path_) +
                " is open read-only: run files are written once, through "
                "File::create");
  return id_;
}

void File::commit() {
  if (committed_) throw Error(in_quotes(path_) + " was already committed");
  const hid_t file = id(true);
  const std::string tmp = path_ + ".tmp";
  if (H5Fflush(file, H5F_SCOPE_GLOBAL) < 0)
    throw Error("cannot write " + in_quotes(tmp) + hdf5_reason() + " (disk full?)");
  id_ = -1;
  if (H5Fclose(file) < 0) throw Error("cannot close " + in_quotes(tmp) + hdf5_reason() + " (disk full?)");
  // Data on disk before the rename makes it visible: a crash leaves the old file or the new.
  fsync_path(tmp, O_RDONLY);
  std::error_code ec;
  fs::rename(tmp, path_, ec);
  if (ec) throw Error("cannot rename " + in_quotes(tmp) + " to " + in_quotes(path_) + ": " + ec.message());
  committed_ = true;
  const fs::path dir = fs::path(path_).parent_path();
  fsync_path(dir.empty() ? "." : dir.string(), O_RDONLY | O_DIRECTORY);
}

bool File::exists(const std::string& path) const { return object_exists(id(false), canonical(path)); }

void File::write(const std::string& path, const std::vector<double>& data) {
  create_and_write(id(true), path_, path, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, {data.size()}, data.data());
}

void File::write(const std::string& path, const std::vector<std::int64_t>& data) {
  create_and_write(id(true), path_, path, H5T_STD_I64LE, H5T_NATIVE_INT64, {data.size()}, data.data());
}

void File::write(const std::string& path, const std::vector<int>& data) {
  create_and_write(id(true), path_, path, H5T_STD_I32LE, H5T_NATIVE_INT, {data.size()}, data.data());
}

void File::write(const std::string& path, const std::vector<std::uint8_t>& data) {
  create_and_write(id(true), path_, path, H5T_STD_U8LE, H5T_NATIVE_UINT8, {data.size()}, data.data());
}

void File::write_rows(const std::string& path, const std::vector<Vec3>& rows) {
  create_and_write(id(true), path_, path, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, {rows.size(), 3},
                   rows.empty() ? nullptr : rows.front().data());
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
    throw Error("cannot read dataset " + in_file(d.path, path_) + hdf5_reason() +
                "; the file may be damaged");
  return out;
}

// ---- attributes

void File::set_attr(const std::string& path, const std::string& name, double value) {
  const Handle space(H5Screate(H5S_SCALAR), H5Sclose);
  write_attr(id(true), path_, path, name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, space.get(), &value);
}

void File::set_attr(const std::string& path, const std::string& name, std::int64_t value) {
  const Handle space(H5Screate(H5S_SCALAR), H5Sclose);
  write_attr(id(true), path_, path, name, H5T_STD_I64LE, H5T_NATIVE_INT64, space.get(), &value);
}

void File::set_attr(const std::string& path, const std::string& name, const std::string& value) {
  write_string_attr(id(true), path_, path, name, {value}, true);
}

void File::set_attr(const std::string& path, const std::string& name,
                    const std::vector<std::int64_t>& values) {
  const hsize_t n = values.size();
  const Handle space(H5Screate_simple(1, &n, nullptr), H5Sclose);
  write_attr(id(true), path_, path, name, H5T_STD_I64LE, H5T_NATIVE_INT64, space.get(), values.data());
}

void File::set_attr(const std::string& path, const std::string& name,
                    const std::vector<std::string>& values) {
  write_string_attr(id(true), path_, path, name, values, false);
}

void File::attr_overflow(const std::string& path, const std::string& name) const {
  throw Error("value of " + attr_where(name, canonical(path), path_) +
              " does not fit in a 64-bit signed integer");
}

bool File::has_attr(const std::string& path, const std::string& name) const {
  const hid_t file = id(false);
  const std::string p = canonical(path);
  if (!object_exists(file, p)) return false;
  const Handle object(H5Oopen(file, p.c_str(), H5P_DEFAULT), H5Oclose);
  const htri_t found = object.ok() ? H5Aexists(object.get(), name.c_str()) : -1;
  H5Eclear2(H5E_DEFAULT);
  return found > 0;
}

double File::get_attr_double(const std::string& path, const std::string& name) const {
  const Attribute a = open_attr(id(false), path_, path, name);
  return only_value(read_numeric_attr<double>(a, Want::Float), a.where, "");
}

std::int64_t File::get_attr_int64(const std::string& path, const std::string& name) const {
  const Attribute a = open_attr(id(false), path_, path, name);
  return only_value(read_numeric_attr<std::int64_t>(a, Want::Int64), a.where, "get_attr_int64s");
}

std::string File::get_attr_string(const std::string& path, const std::string& name) const {
  const Attribute a = open_attr(id(false), path_, path, name);
  return only_value(read_string_attr(a), a.where, "get_attr_strings");
}

std::vector<std::int64_t> File::get_attr_int64s(const std::string& path, const std::string& name) const {
  const Attribute a = open_attr(id(false), path_, path, name);
  return read_numeric_attr<std::int64_t>(a, Want::Int64);
}

std::vector<std::string> File::get_attr_strings(const std::string& path, const std::string& name) const {
  return read_string_attr(open_attr(id(false), path_, path, name));
}

// ================================================================ Series

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
  if (H5Zfilter_avail(H5Z_FILTER_DEFLATE) > 0) {
    H5Pset_shuffle(dcpl.get());
    H5Pset_deflate(dcpl.get(), 1);
  }
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

// ================================================================ H5MD

void write_h5md_header(File& file, const std::string& creator_version, const std::string& author) {
  file.set_attr("/h5md", "version", std::vector<std::int64_t>{1, 1});
  file.set_attr("/h5md/author", "name", author.empty() ? login_name() : author);
  file.set_attr("/h5md/creator", "name", std::string("granudrag"));
  file.set_attr("/h5md/creator", "version", creator_version);
}

}  // namespace granudrag::h5
