#pragma once
// Contiguous ranges of about equal cost, for threads that each take one range of an array
// (its cache lines then stay with one core from step to step).
#include <vector>

namespace granudrag {

// prefix[i] is the cost of items 0 .. i-1 (prefix[0] = 0, prefix.size() = n + 1). On return
// part k is items bounds[k] .. bounds[k+1] - 1, for k < parts: bounds[0] = 0, bounds[parts] = n,
// and part k ends at the first item whose running cost reaches k + 1 parts' share.
inline void balanced_split(const std::vector<long>& prefix, int parts, std::vector<long>& bounds) {
  const long n = static_cast<long>(prefix.size()) - 1;
  bounds.assign(parts + 1, n);
  bounds[0] = 0;
  long i = 0;
  for (int k = 1; k < parts; ++k) {
    const long target = prefix[n] * k / parts;
    while (i < n && prefix[i] < target) ++i;
    bounds[k] = i;
  }
}

}  // namespace granudrag
