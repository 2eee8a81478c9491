#include "io/hdf5_internals.hpp"

#include <mutex>

namespace granudrag::h5::detail {

namespace {

herr_t keep_deepest(unsigned, const H5E_error2_t* e, void* out) {
  if (e->desc != nullptr && e->desc[0] != '\0') *static_cast<std::string*>(out) = e->desc;
  return 0;
}

}  // namespace

// HDF5 prints its whole error stack to stderr by default; we report one line instead.
void silence_hdf5() {
  static std::once_flag once;
  std::call_once(once, [] {
    // No library shutdown at exit: after a write failed half-way (disk full), HDF5 keeps the
    // file it could not close and its shutdown then crashed on it (SIGSEGV in H5F__close_cb)
    // after the error was printed. Every file is closed by its h5::File before exit anyway.
    // Must come before any other HDF5 call.
    H5dont_atexit();
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
    // No free lists: HDF5 would keep freed blocks for its own reuse (the system allocator
    // does that as well), and with no shutdown at exit the leak checker of the sanitizer
    // build then reported blocks of those lists as leaked (after the frame tests, in a later
    // test's reads of damaged files).
    H5set_free_list_limits(0, 0, 0, 0, 0, 0);
  });
}

// The innermost message of HDF5's error stack (the most specific: "truncated file: eof = ...")
// as " (HDF5: ...)". Must be called right after the failing call: any other HDF5 call clears it.
std::string hdf5_reason() {
  std::string reason;
  H5Ewalk2(H5E_DEFAULT, H5E_WALK_DOWNWARD, keep_deepest, &reason);
  H5Eclear2(H5E_DEFAULT);
  // A failed write says much ("file write failed: time = ..., filename = ..., errno = 27,
  // error message = 'File too large', buf = ..."): keep what it was and the system's reason.
  if (const auto at = reason.find("error message = '"); at != std::string::npos) {
    const auto start = at + 17, end = reason.find('\'', start);
    reason = reason.substr(0, reason.find(':')) + ": " + reason.substr(start, end - start);
  }
  return reason.empty() ? std::string() : " (HDF5: " + reason + ")";
}

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

void set_compression(hid_t dcpl) {
  if (H5Zfilter_avail(H5Z_FILTER_DEFLATE) <= 0) return;
  H5Pset_shuffle(dcpl);
  H5Pset_deflate(dcpl, 1);
}

void set_checksum(hid_t dcpl) { H5Pset_fletcher32(dcpl); }

std::string read_failure() {
  const std::string reason = hdf5_reason();
  if (reason.find("Fletcher32") != std::string::npos || reason.find("checksum") != std::string::npos)
    return ": its checksum fails, the file was damaged after it was written; regenerate it (pour or "
           "pull again)";
  return reason + "; the file may be damaged";
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

// Written here, a dataset's chunks hold their data whole (Fletcher-32 is the only filter), so it
// stores at least count x element size bytes. A damaged chunk index can declare a chunk shorter
// than that, and HDF5 (1.10) then copies the full chunk out of the short buffer it read: a heap
// overflow, seen under AddressSanitizer with one flipped bit in a checkpoint. Such a dataset is
// refused by name. Datasets compressed by other tools (any other filter) are left to HDF5.
void require_stored_data(const Dataset& d, const std::string& file_name, std::size_t element_size) {
  if (d.count == 0) return;
  const Handle dcpl(H5Dget_create_plist(d.dset.get()), H5Pclose);
  if (!dcpl.ok()) return;
  const int filters = H5Pget_nfilters(dcpl.get());
  for (int k = 0; k < filters; ++k) {
    unsigned flags = 0;
    std::size_t n = 0;
    if (H5Pget_filter2(dcpl.get(), static_cast<unsigned>(k), &flags, &n, nullptr, 0, nullptr, nullptr) !=
        H5Z_FILTER_FLETCHER32)
      return;
  }
  const hsize_t stored = H5Dget_storage_size(d.dset.get());
  const hsize_t needed = static_cast<hsize_t>(d.count) * element_size;
  if (stored < needed)
    throw Error("dataset " + in_file(d.path, file_name) + " is damaged: it stores " + std::to_string(stored) +
                " bytes for " + std::to_string(d.count) + " values of " + std::to_string(element_size) +
                " bytes; regenerate the file");
}

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
  require_stored_data(d, file_name, H5Tget_size(type.get()));
  return d;
}

void require_shape(const Dataset& d, const std::string& file_name, std::size_t rank, std::size_t columns,
                   const char* expected) {
  const bool ok = d.dims.size() == rank && (rank < 2 || d.dims[1] == columns);
  if (!ok)
    throw Error("dataset " + in_file(d.path, file_name) + " has shape " + shape_text(d.dims) + ", expected " +
                expected);
}

}  // namespace granudrag::h5::detail
