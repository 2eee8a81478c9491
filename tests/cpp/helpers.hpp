#pragma once
// Small systems for the tests.
#include <gtest/gtest.h>
#include <omp.h>

#include <cmath>
#include <utility>
#include <vector>

#include "core/error.hpp"
#include "engine/simulation.hpp"
#include "protocol/lattice_bed.hpp"
#include "protocol/pour.hpp"
#include "protocol/pull.hpp"

namespace granudrag::support {

// The paper's contact set softened to K_n = 2e5 (same restitution curve), for fast tests.
inline ContactParams soft_params(double mu = 0.5) {
  ContactParams c = ContactParams{}.with_stiffness(2.0e5);
  c.mu = mu;
  return c;
}

inline ContactParams conservative_params() {
  ContactParams c = soft_params(0.0);
  c.gamman = c.gammat = 0.0;
  return c;
}

// One shared small poured bed: 1200 soft frictional grains in a 10 d x 10 d box, D = 2 at depth 4.
inline const Bed& small_bed() {
  static const Bed bed = [] {
    PourSpec s;
    s.lx = s.ly = 10;
    s.grains = 1200;
    s.intruder_diameter = 2;
    s.intruder_x = s.intruder_y = 5;
    s.depth = 4;
    s.contact = ContactParams{}.with_stiffness(2e4);
    s.ke_threshold = 1e-4;
    s.max_settle_time = 40;
    return pour(s, false);
  }();
  return bed;
}

// Runs a pull to its end and keeps what each of its checkpoints saves (state and record), for
// the resume tests: "kill" after checkpoint k, resume from checkpoints[k].
using Checkpoints = std::vector<std::pair<Simulation::State, PullRecord>>;
inline Checkpoints run_keeping_checkpoints(Pull& pull) {
  Checkpoints out;
  pull.run(false, [&](const Pull& p) { out.emplace_back(p.state(), p.record()); });
  return out;
}

// Whether two runs left every body in the same place, at the same velocity and spin, bit for
// bit (the resume tests); names the first body that differs.
inline ::testing::AssertionResult same_motion(const Particles& a, const Particles& b) {
  if (a.size() != b.size())
    return ::testing::AssertionFailure() << a.size() << " bodies against " << b.size();
  for (std::size_t i = 0; i < a.size(); ++i)
    if (a.x[i] != b.x[i] || a.v[i] != b.v[i] || a.omega[i] != b.omega[i])
      return ::testing::AssertionFailure() << "body " << i << " differs";
  return ::testing::AssertionSuccess();
}

// Relative difference of two vectors on the scale `scale`.
inline double rel_diff(const Vec3& a, const Vec3& b, double scale) { return (a - b).norm() / scale; }

// Restores the thread count a test changed.
class ThreadCount {
 public:
  explicit ThreadCount(int n) : saved_(omp_get_max_threads()) { omp_set_num_threads(n); }
  ~ThreadCount() { omp_set_num_threads(saved_); }

 private:
  int saved_;
};

}  // namespace granudrag::support
