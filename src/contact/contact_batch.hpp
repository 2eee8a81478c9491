#pragma once
// The contact law over a batch of touching pairs, in structure-of-arrays form so that the
// compiler evaluates several pairs per instruction (SIMD). It is hertz_history (contact_law.hpp)
// written lane by lane: same operations, same order, branches turned into selects, so a pair's
// force, torque and spring come out as the scalar law gives them (tests/cpp/test_contact_batch.cpp
// holds it to that, on random states).
//
// Why batches: in a bed about half the entries of a Verlet list touch, at random, so a loop that
// branches on "touching?" mispredicts about every other pair, and the law's chain of square roots
// and divisions then runs one pair at a time. Finding the touching pairs first (branch-free) and
// evaluating them together removes both costs.
#include <string>

#include "contact/contact_params.hpp"

namespace granudrag {

struct ContactBatch {
  // 128 pairs x 22 arrays x 8 bytes = 22 kB, inside a 32-48 kB L1. Force loop of the 7.7k pull,
  // 1 thread: 1.13 s with 32 lanes, 1.07 s with 64, 1.06 s with 128.
  static constexpr int kCapacity = 128;
  int size = 0;

  // Inputs, set by the caller for lanes 0 .. size-1.
  alignas(64) double dx[kCapacity], dy[kCapacity], dz[kCapacity];  // r_i - r_j (minimum image)
  alignas(64) double rsq[kCapacity];                               // |r_i - r_j|^2 < radsum^2
  alignas(64) double radsum[kCapacity], reff[kCapacity], meff[kCapacity];
  alignas(64) double vx[kCapacity], vy[kCapacity], vz[kCapacity];  // v_i - v_j
  alignas(64) double wx[kCapacity], wy[kCapacity], wz[kCapacity];  // R_i w_i + R_j w_j
  // The tangential spring: read, and written back updated.
  alignas(64) double sx[kCapacity], sy[kCapacity], sz[kCapacity];
  // Outputs: force on i (j gets minus it) and the lever-free torque (PairForce::torque).
  alignas(64) double fx[kCapacity], fy[kCapacity], fz[kCapacity];
  alignas(64) double tx[kCapacity], ty[kCapacity], tz[kCapacity];
  // Which pair each lane is, for the caller's scatter; the kernel does not read them.
  int i[kCapacity], j[kCapacity], entry[kCapacity];
};

// The instruction sets the batch law is compiled for (x86-64 baseline = SSE2, x86-64-v3 = AVX2,
// x86-64-v4 = AVX-512), in increasing order.
enum class SimdLevel { Baseline, Avx2, Avx512 };
SimdLevel cpu_simd_level();  // the widest this CPU runs
// What runs: cpu_simd_level(), or a narrower level named by the environment variable
// GRANUDRAG_SIMD=baseline|avx2|avx512 (to compare them, or to rule the wide ones out). Throws
// granudrag::Error for another name or a level the CPU does not run.
SimdLevel best_simd_level();
const char* simd_level_key(SimdLevel level);         // "baseline", "avx2", "avx512"
SimdLevel parse_simd_level(const std::string& key);  // its inverse; granudrag::Error otherwise

// Evaluates lanes 0 .. b.size-1. update_history as in hertz_history. The overload with a level
// runs that variant (the tests compare each with the scalar law); the CPU must support it.
void hertz_history_batch(const ContactParams& p, double dt, bool update_history, ContactBatch& b);
void hertz_history_batch(const ContactParams& p, double dt, bool update_history, ContactBatch& b,
                         SimdLevel level);

}  // namespace granudrag
