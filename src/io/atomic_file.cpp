#include "io/atomic_file.hpp"

#include <cstdio>
#include <fstream>

#include "core/error.hpp"

namespace granudrag {

void write_file_atomically(const std::string& path, const std::string& content) {
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary);
    if (!out) throw Error("cannot write '" + tmp + "': check that its directory exists and is writable");
    out << content;
    out.flush();
    if (!out) throw Error("writing '" + tmp + "' failed (disk full?)");
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0)
    throw Error("cannot rename '" + tmp + "' to '" + path + "'");
}

}  // namespace granudrag
