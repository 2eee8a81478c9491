#pragma once
// Text files that appear whole or not at all: written to `path.tmp`, then renamed over `path`,
// so a reader (or a workflow that checks for the file) never sees half of one. The HDF5 files
// do the same through h5::File::create/commit.
#include <string>

namespace granudrag {

// Throws Error naming the file when it cannot be written or renamed.
void write_file_atomically(const std::string& path, const std::string& content);

}  // namespace granudrag
