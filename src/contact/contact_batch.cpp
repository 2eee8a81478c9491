#include "contact/contact_batch.hpp"

#include <cmath>
#include <cstdlib>
#include <string>

#include "core/error.hpp"

// Wider vectors are chosen at run time, so that one binary serves every node of a cluster. The
// file is compiled with -ffp-contract=off (CMakeLists.txt): no variant fuses a multiply and an
// add that another rounds twice, so all give the same bits, and a run resumed on another kind of
// node continues bitwise.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define GRANUDRAG_X86_DISPATCH 1
#else
#define GRANUDRAG_X86_DISPATCH 0
#endif

namespace granudrag {

namespace {

// update_history is a template argument: a branch inside the loop would keep it from vectorising.
template <bool update_history>
[[gnu::always_inline]] inline void evaluate(const ContactParams& p, double dt, ContactBatch& b) {
  const double kn = p.kn, kt = p.kt, gamman = p.gamman, gammat = p.gammat, mu = p.mu;
  const int n = b.size;
#pragma omp simd
  for (int k = 0; k < n; ++k) {
    const double dx = b.dx[k], dy = b.dy[k], dz = b.dz[k];
    const double vx = b.vx[k], vy = b.vy[k], vz = b.vz[k];
    const double wx = b.wx[k], wy = b.wy[k], wz = b.wz[k];
    const double meff = b.meff[k];

    const double r = std::sqrt(b.rsq[k]);
    const double rinv = 1.0 / r;
    const double rsqinv = rinv * rinv;
    const double delta = b.radsum[k] - r;

    const double vnnr = vx * dx + vy * dy + vz * dz;
    const double vn = vnnr * rsqinv;
    // Tangential velocity at the contact: v - n (v.n) + (del x spin_sum) / r.
    const double vrx = (vx - dx * vn) + (dy * wz - dz * wy) * rinv;
    const double vry = (vy - dy * vn) + (dz * wx - dx * wz) * rinv;
    const double vrz = (vz - dz * vn) + (dx * wy - dy * wx) * rinv;

    const double polyhertz = std::sqrt(delta * b.reff[k]);
    const double ccel = polyhertz * (kn * delta * rinv - meff * gamman * vnnr * rsqinv);

    double sx = b.sx[k], sy = b.sy[k], sz = b.sz[k];
    if constexpr (update_history) {
      sx += vrx * dt;
      sy += vry * dt;
      sz += vrz * dt;
    }
    const double shrmag = std::sqrt(sx * sx + sy * sy + sz * sz);
    if constexpr (update_history) {
      const double rsht = (sx * dx + sy * dy + sz * dz) * rsqinv;
      sx -= dx * rsht;
      sy -= dy * rsht;
      sz -= dz * rsht;
    }

    const double damp = meff * gammat;
    double fsx = -polyhertz * (kt * sx + damp * vrx);
    double fsy = -polyhertz * (kt * sy + damp * vry);
    double fsz = -polyhertz * (kt * sz + damp * vrz);
    const double fs_mag = std::sqrt(fsx * fsx + fsy * fsy + fsz * fsz);
    const double fn_cap = mu * std::abs(ccel * r);
    // Coulomb cap, as selects: ratio is computed in every lane and used only where the pair
    // slips (fs_mag > fn_cap) and, for the spring, where it has one (shrmag != 0).
    const double ratio = fn_cap / fs_mag;
    const double as_spring = damp / kt;
    const double ax = vrx * as_spring, ay = vry * as_spring, az = vrz * as_spring;
    sx = (fs_mag > fn_cap && shrmag != 0.0) ? ratio * (sx + ax) - ax : sx;
    sy = (fs_mag > fn_cap && shrmag != 0.0) ? ratio * (sy + ay) - ay : sy;
    sz = (fs_mag > fn_cap && shrmag != 0.0) ? ratio * (sz + az) - az : sz;
    const double fs_scale = (fs_mag > fn_cap && shrmag != 0.0) ? ratio : 0.0;
    fsx = (fs_mag > fn_cap) ? fsx * fs_scale : fsx;
    fsy = (fs_mag > fn_cap) ? fsy * fs_scale : fsy;
    fsz = (fs_mag > fn_cap) ? fsz * fs_scale : fsz;

    b.sx[k] = sx;
    b.sy[k] = sy;
    b.sz[k] = sz;
    b.fx[k] = dx * ccel + fsx;
    b.fy[k] = dy * ccel + fsy;
    b.fz[k] = dz * ccel + fsz;
    b.tx[k] = (dy * fsz - dz * fsy) * rinv;
    b.ty[k] = (dz * fsx - dx * fsz) * rinv;
    b.tz[k] = (dx * fsy - dy * fsx) * rinv;
  }
}

template <bool update_history>
void evaluate_baseline(const ContactParams& p, double dt, ContactBatch& b) {
  evaluate<update_history>(p, dt, b);
}

#if GRANUDRAG_X86_DISPATCH
// The same loop compiled for wider vectors; the attribute lets the compiler use them here only.
template <bool update_history>
__attribute__((target("arch=x86-64-v3"))) void evaluate_avx2(const ContactParams& p, double dt,
                                                             ContactBatch& b) {
  evaluate<update_history>(p, dt, b);
}
template <bool update_history>
__attribute__((target("arch=x86-64-v4"))) void evaluate_avx512(const ContactParams& p, double dt,
                                                               ContactBatch& b) {
  evaluate<update_history>(p, dt, b);
}
#endif

}  // namespace

SimdLevel cpu_simd_level() {
#if GRANUDRAG_X86_DISPATCH
  __builtin_cpu_init();
  if (__builtin_cpu_supports("x86-64-v4")) return SimdLevel::Avx512;
  if (__builtin_cpu_supports("x86-64-v3")) return SimdLevel::Avx2;
#endif
  return SimdLevel::Baseline;
}

SimdLevel parse_simd_level(const std::string& name) {
  for (SimdLevel level : {SimdLevel::Baseline, SimdLevel::Avx2, SimdLevel::Avx512})
    if (name == simd_level_key(level)) return level;
  throw Error("GRANUDRAG_SIMD='" + name +
              "' is not an instruction set: use baseline, avx2 or avx512 (or unset it)");
}

SimdLevel best_simd_level() {
  static const SimdLevel best = [] {
    const SimdLevel cpu = cpu_simd_level();
    const char* requested = std::getenv("GRANUDRAG_SIMD");
    if (!requested || !*requested) return cpu;
    const SimdLevel level = parse_simd_level(requested);
    if (level > cpu)
      throw Error(std::string("GRANUDRAG_SIMD=") + requested + ": this CPU runs at most " +
                  simd_level_key(cpu) + "; ask for that or less (or unset it)");
    return level;
  }();
  return best;
}

const char* simd_level_key(SimdLevel level) {
  switch (level) {
    case SimdLevel::Avx512:
      return "avx512";
    case SimdLevel::Avx2:
      return "avx2";
    case SimdLevel::Baseline:
      break;
  }
  return "baseline";
}

void hertz_history_batch(const ContactParams& p, double dt, bool update_history, ContactBatch& b,
                         SimdLevel level) {
#if GRANUDRAG_X86_DISPATCH
  if (level == SimdLevel::Avx512)
    return update_history ? evaluate_avx512<true>(p, dt, b) : evaluate_avx512<false>(p, dt, b);
  if (level == SimdLevel::Avx2)
    return update_history ? evaluate_avx2<true>(p, dt, b) : evaluate_avx2<false>(p, dt, b);
#endif
  (void)level;
  return update_history ? evaluate_baseline<true>(p, dt, b) : evaluate_baseline<false>(p, dt, b);
}

void hertz_history_batch(const ContactParams& p, double dt, bool update_history, ContactBatch& b) {
  hertz_history_batch(p, dt, update_history, b, best_simd_level());
}

}  // namespace granudrag
