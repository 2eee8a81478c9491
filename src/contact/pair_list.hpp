#pragma once
// A list of pairs in compressed-row form: row r owns partner[offset[r] .. offset[r+1]),
// each row sorted by partner index so that two lists can be merged in linear time.
#include <cstddef>
#include <vector>

namespace granudrag {

struct PairList {
  std::vector<int> offset{0};
  std::vector<int> partner;

  std::size_t rows() const { return offset.size() - 1; }
  std::size_t size() const { return partner.size(); }
  int begin(std::size_t row) const { return offset[row]; }
  int end(std::size_t row) const { return offset[row + 1]; }
};

}  // namespace granudrag
