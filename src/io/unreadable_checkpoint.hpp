#pragma once
// What a run does with a checkpoint it cannot read: a killed job retried by a scheduler must
// always make progress, so a damaged checkpoint is moved aside and the run starts over, while a
// readable one written with other options stays an error (that decision is the user's).
#include <cstdio>
#include <optional>
#include <string>

#include "core/error.hpp"

namespace granudrag {

// A checkpoint that cannot be read at all: truncated, corrupt, not HDF5, of another format or
// version, arrays short or of the wrong type.
class UnreadableCheckpoint : public Error {
 public:
  using Error::Error;
};

// load(), except that an UnreadableCheckpoint renames `path` to `<path>.corrupt` (replacing an
// older one), says so on stderr and returns nothing: the run starts over.
template <class Load>
auto load_or_move_aside(const std::string& path, Load load) -> std::optional<decltype(load())> {
  try {
    return load();
  } catch (const UnreadableCheckpoint& e) {
    const std::string aside = path + ".corrupt";
    if (std::rename(path.c_str(), aside.c_str()) != 0)
      throw Error(std::string(e.what()) + "; moving it aside to '" + aside +
                  "' failed too: delete it by hand");
    std::fprintf(stderr, "granudrag: %s\ngranudrag: moved it aside to '%s' and starting over\n", e.what(),
                 aside.c_str());
    return std::nullopt;
  }
}

}  // namespace granudrag
