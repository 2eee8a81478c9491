#include "io/file_header.hpp"

#include <hdf5.h>

#include <filesystem>

#include "core/build_stamp.hpp"
#include "core/error.hpp"
#include "io/hdf5_internals.hpp"

namespace granudrag {

void write_file_header(h5::File& file, const std::string& format) {
  h5::write_h5md_header(file, std::string(GRANUDRAG_VERSION) + " (" + build_commit() + ")");
  file.set_attr("/granudrag", "format", format);
  file.set_attr("/granudrag", "version", kFileVersion);
  file.set_attr("/granudrag", "code_version", std::string(GRANUDRAG_VERSION));
  file.set_attr("/granudrag", "commit", std::string(build_commit()));
}

std::int64_t check_file_header(const h5::File& file, const std::string& format, std::int64_t oldest,
                               const std::string& remedy) {
  const std::string& path = file.path();
  if (!file.has_attr("/granudrag", "format"))
    throw Error("'" + path + "' is not a granudrag file (no /granudrag format attribute)");
  const std::string got = file.get_attr_string("/granudrag", "format");
  if (got != format) throw Error("'" + path + "' is a " + got + " file, not a " + format + " file");
  const std::int64_t version = file.get_attr_int64("/granudrag", "version");
  if (version < oldest || version > kFileVersion) {
    const std::string readable =
        oldest == kFileVersion ? "version " + std::to_string(kFileVersion)
                               : "versions " + std::to_string(oldest) + " to " + std::to_string(kFileVersion);
    throw Error("'" + path + "' has format version " + std::to_string(version) + "; this granudrag reads " +
                readable + " of " + format + " files: " + remedy);
  }
  return version;
}

std::string file_kind(const std::string& path) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);
  if (ec || !fs::exists(st)) return "missing";
  if (fs::is_directory(st)) return "directory";
  if (fs::is_regular_file(st) && fs::file_size(path, ec) == 0 && !ec) return "empty";
  h5::detail::silence_hdf5();
  htri_t is_hdf5 = -1;
  H5E_BEGIN_TRY { is_hdf5 = H5Fis_hdf5(path.c_str()); }
  H5E_END_TRY;
  if (is_hdf5 <= 0) return "other";
  try {
    const h5::File f = h5::File::open(path);
    if (!f.has_attr("/granudrag", "format")) return "hdf5";
    return f.get_attr_string("/granudrag", "format");
  } catch (const Error&) {
    return "unreadable-hdf5";
  }
}

}  // namespace granudrag
