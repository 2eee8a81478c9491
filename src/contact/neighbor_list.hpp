#pragma once
// Verlet lists with a skin, built from a cell grid and rebuilt when any body has moved more
// than half the skin since the last build.
//
// Two lists, so that a large intruder does not inflate the cost for everyone:
//  - grain pairs: a half list (row i holds partners j > i) from a grid whose cells fit the
//    largest grain, not the intruder; frozen-frozen pairs are left out.
//  - intruder pairs: one row per intruder, holding every grain within reach of it, found by
//    scanning only the cells its sphere covers.
#include <cstdint>
#include <vector>

#include "contact/pair_list.hpp"
#include "core/box.hpp"
#include "core/particles.hpp"

namespace granudrag {

class NeighborList {
 public:
  explicit NeighborList(double skin) : skin_(skin) {}

  double skin() const { return skin_; }
  // Whether the lists of n bodies are due for a rebuild, given the largest squared displacement
  // of any body from build_positions() since the last build (measured by the integrator in its
  // drift; NaN or HUGE_VAL: rebuild, and a NaN position is then reported).
  bool rebuild_due(std::size_t n, double max_drift_sq) const;
  const std::vector<Vec3>& build_positions() const { return x_at_build_; }
  // Wraps positions into the box, then rebuilds both lists. The previous lists are kept
  // so that contact histories can follow their pairs (ContactHistory::carry_over).
  void build(Particles& p, const Box& box);

  const PairList& grain_pairs() const { return grain_; }
  // Per row of grain_pairs(): 1 if a partner lay across a periodic boundary at the build (x_j
  // and x_i more than half a box apart). The others need no minimum image until the next build:
  // without wrapping, a pair's separation moves by less than a skin between builds.
  const std::vector<std::uint8_t>& wrapping_rows() const { return wrapping_rows_; }
  const PairList& previous_grain_pairs() const { return grain_prev_; }
  const PairList& intruder_pairs() const { return intruder_; }
  const PairList& previous_intruder_pairs() const { return intruder_prev_; }
  const std::vector<int>& intruder_bodies() const { return intruder_bodies_; }
  long builds() const { return builds_; }

 private:
  struct Grid {
    int nx = 0, ny = 0, nz = 0;
    double cx = 0, cy = 0, cz = 0, z0 = 0;
    std::vector<int> start, items;  // counting-sorted grains per cell
    int cell_z(double z) const;
  };
  void bin(const Particles& p, const Box& box, double cell_size);
  void build_grain_pairs(const Particles& p, const Box& box, double max_grain_radius);
  void build_intruder_pairs(const Particles& p, const Box& box, double max_grain_radius);

  double skin_;
  Grid grid_;
  PairList grain_, grain_prev_, intruder_, intruder_prev_;
  std::vector<int> intruder_bodies_;
  std::vector<Vec3> x_at_build_;
  std::vector<std::uint8_t> wrapping_rows_;
  std::vector<int> cell_of_;              // per body, its cell (-1: an intruder); kept between builds
  std::vector<std::vector<int>> chunks_;  // per thread, the rows it built
  long builds_ = 0;
};

}  // namespace granudrag
