#pragma once
// The tangential springs of a pair list, one per entry. They belong to the pair, not to the
// list: when the neighbour list is rebuilt, carry_over() moves each surviving pair's spring to
// its new slot, so history survives rebuilds (keyed by the pair's identity: row and partner).
#include <cstdint>
#include <vector>

#include "contact/pair_list.hpp"
#include "core/vec3.hpp"

namespace granudrag {

struct ContactHistory {
  std::vector<Vec3> shear;
  std::vector<std::uint8_t> touching;  // was the pair in contact at the last force evaluation

  void resize(std::size_t n) {
    shear.assign(n, Vec3::Zero());
    touching.assign(n, 0);
  }
  // Re-key from `before` to `after` (same rows); pairs new in `after` start with no history.
  void carry_over(const PairList& before, const PairList& after);

 private:
  // The arrays of the previous list, kept for the next carry-over: a fresh allocation each
  // rebuild costs a page fault per 4 kB and a serial clearing pass (7.5 MB at 70,000 grains).
  std::vector<Vec3> spare_shear_;
  std::vector<std::uint8_t> spare_touching_;
};

}  // namespace granudrag
