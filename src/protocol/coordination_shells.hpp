#pragma once
// Z against the width of the shell it is measured in. The paper counts the contacts of grains
// "within a certain distance from the intruder" (Sec. III B, Eq. 8) without stating the
// distance, and kappa = (Z/n)(D+d)^2/(2 sqrt(3) d^2) depends on it: the wake's floaters sit
// next to the intruder, so a narrow shell sees Z fall with Fr as fast as n, a wide one mostly
// undisturbed bed. Every pull therefore also records Z in nested shells R + w for the widths
// below, from the same samples as its main Z (pull.hpp, `shell`).
#include <array>
#include <vector>

namespace granudrag {

struct CoordinationShells {
  // Shell widths w beyond the intruder's radius, d (a grain touching the intruder has its
  // centre within R + 0.55 d).
  static constexpr std::array<double, 9> widths = {0.5, 1.0, 1.5, 2.0, 2.5, 3.0, 4.0, 5.0, 6.0};
  static constexpr int rings = static_cast<int>(widths.size());

  // Per ring k: grains with centre in [R + w_{k-1}, R + w_k) (w_{-1} = -infinity) summed over
  // the samples, and their contacts.
  std::vector<long> grains = std::vector<long>(rings, 0);
  std::vector<long> contacts = std::vector<long>(rings, 0);

  // The ring of a grain whose centre is `gap` beyond the intruder's radius; -1: outside all.
  static int ring(double gap) {
    for (int k = 0; k < rings; ++k)
      if (gap < widths[k]) return k;
    return -1;
  }

  // Z within R + w_k for each k (NaN where no grain was seen).
  std::vector<double> z() const {
    std::vector<double> out;
    long g = 0, c = 0;
    for (int k = 0; k < rings; ++k) {
      g += grains[k];
      c += contacts[k];
      out.push_back(g > 0 ? static_cast<double>(c) / g : __builtin_nan(""));
    }
    return out;
  }
};

}  // namespace granudrag
