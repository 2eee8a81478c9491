#pragma once
// What every granudrag file starts with: the H5MD header (/h5md: version, author, creator) and
// /granudrag attributes `format` ("granudrag-bed", "granudrag-run", "granudrag-checkpoint"),
// `version` (kFileVersion), `code_version` and `commit` of the binary that wrote it.
#include <cstdint>
#include <string>

#include "io/h5_file.hpp"

namespace granudrag {

// The layout's version, one for all three kinds of file:
//   1  the resolved parameters as one YAML text (/parameters attribute `yaml`)
//   2  the parameters by key: /parameters/pour, /parameters/pull (io/parameter_record.hpp)
//   3  every dataset with data carries HDF5's Fletcher-32 checksum, checked on every read
//      (io/hdf5_internals.hpp); the layout is version 2's
constexpr std::int64_t kFileVersion = 3;
// The first version whose datasets carry checksums.
constexpr std::int64_t kFirstChecksummedVersion = 3;

void write_file_header(h5::File& file, const std::string& format);

// The file's version, when `file` is a `format` file of a version from `oldest` to kFileVersion.
// Otherwise an Error naming the file, what it is, and `remedy` (what to do about an old or new
// version: "re-create it with this granudrag", say).
std::int64_t check_file_header(const h5::File& file, const std::string& format, std::int64_t oldest,
                               const std::string& remedy);

// What is at `path`, for refusing to overwrite a file of another kind: "missing", "directory",
// "empty", the /granudrag format of a granudrag file ("granudrag-bed", ...), "hdf5" (an HDF5 file
// without one), "unreadable-hdf5" (an HDF5 signature but it cannot be opened: truncated or
// corrupt) or "other" (not HDF5: text, say). Never throws for what the file holds.
std::string file_kind(const std::string& path);

}  // namespace granudrag
