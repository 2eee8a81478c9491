// File: opening, creating and committing a file (atomically), and the H5MD header.
#include "io/h5_file.hpp"

#include <fcntl.h>
#include <hdf5.h>
#include <pwd.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <utility>

#include "core/error.hpp"
#include "io/hdf5_internals.hpp"

namespace granudrag::h5 {

static_assert(std::is_same_v<hid_t, std::int64_t>,
              "h5_file.hpp stores HDF5 ids as std::int64_t, which needs HDF5 >= 1.10");
static_assert(sizeof(Vec3) == 3 * sizeof(double),
              "std::vector<Vec3> is read and written as one N x 3 block of doubles");
static_assert(sizeof(int) == 4, "int datasets are stored as 32-bit integers");

using namespace detail;
namespace fs = std::filesystem;

namespace {

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

File File::create(const std::string& path, Compression compression) {
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
  // Every dataset is chunked (for its checksum), most of them into one chunk: the chunk index's
  // B-tree nodes at their smallest (HDF5 allocates 2k entries per node; k = 32 by default made
  // a run file three times larger, mostly empty nodes).
  const Handle fcpl(H5Pcreate(H5P_FILE_CREATE), H5Pclose);
  H5Pset_istore_k(fcpl.get(), 1);
  const hid_t id = H5Fcreate(tmp.c_str(), H5F_ACC_TRUNC, fcpl.get(), fapl.get());
  if (id < 0)
    throw Error("cannot create " + in_quotes(tmp) + hdf5_reason() +
                ": check that its directory is writable and that no other run is writing it");
  File f;
  f.id_ = id;
  f.path_ = path;
  f.writable_ = true;
  f.compression_ = compression;
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
      committed_(other.committed_),
      compression_(other.compression_) {}

File& File::operator=(File&& other) noexcept {
  if (this != &other) {
    close_quietly();
    id_ = std::exchange(other.id_, -1);
    path_ = std::move(other.path_);
    writable_ = std::exchange(other.writable_, false);
    committed_ = other.committed_;
    compression_ = other.compression_;
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

void File::create_group(const std::string& path) {
  const std::string p = canonical(path);
  const hid_t file = id(true);
  if (object_exists(file, p) && kind_of(file, p) != H5I_GROUP)
    throw Error("cannot create group " + in_file(p, path_) + ": a dataset is there");
  open_object(file, path_, p, true);
}

void write_h5md_header(File& file, const std::string& creator_version, const std::string& author) {
  file.set_attr("/h5md", "version", std::vector<std::int64_t>{1, 1});
  file.set_attr("/h5md/author", "name", author.empty() ? login_name() : author);
  file.set_attr("/h5md/creator", "name", std::string("granudrag"));
  file.set_attr("/h5md/creator", "version", creator_version);
}

}  // namespace granudrag::h5
