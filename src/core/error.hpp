#pragma once
#include <stdexcept>
#include <string>

namespace granudrag {
// Every error a user can cause or act on: bad input, an unstable run, a missing file.
// Thrown anywhere, caught once in main() and printed without a stack of noise.
class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& what) : std::runtime_error(what) {}
};
}  // namespace granudrag
