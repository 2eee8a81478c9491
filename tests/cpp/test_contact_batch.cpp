// The vectorised contact law (contact_batch.hpp) against the scalar one (contact_law.hpp), the
// oracle every fast path answers to: random touching pairs, every instruction-set variant this
// CPU runs, with and without the history update, sticking and slipping, with and without a
// spring. Agreement to 1e-12 relative; in practice the bits are equal, since the batch performs
// the scalar law's operations in its order.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <vector>

#include "contact/contact_batch.hpp"
#include "contact/contact_law.hpp"
#include "helpers.hpp"

using namespace granudrag;

namespace {

struct Lane {
  ContactGeometry g;
  Vec3 shear;
};

// A random touching pair. Every fourth has no spring yet (a new contact), every third a spring
// large enough that the pair slips; frozen partners and the intruder's size come up too.
Lane random_lane(std::mt19937_64& rng, int k) {
  std::uniform_real_distribution<double> u(-1.0, 1.0), rad(0.45, 0.55), ov(1e-6, 2e-2);
  const double ri = rad(rng), rj = (k % 7 == 0) ? 1.0 : rad(rng);
  Vec3 n(u(rng), u(rng), u(rng));
  n.normalize();
  const Vec3 del = (ri + rj - ov(rng)) * n;
  const double r = std::sqrt(del.squaredNorm());  // as the Verlet path computes it
  const Species kj = (k % 5 == 0) ? Species::Frozen : Species::Mobile;
  Lane lane;
  lane.g = {del,
            r,
            ri + rj,
            ri * rj / (ri + rj),
            effective_mass(sphere_mass(ri), Species::Mobile, sphere_mass(rj), kj),
            Vec3(u(rng), u(rng), u(rng)),
            3.0 * Vec3(u(rng), u(rng), u(rng))};
  const double spring = (k % 3 == 0) ? 0.5 : 1e-3;
  lane.shear = (k % 4 == 0) ? Vec3::Zero() : Vec3(spring * Vec3(u(rng), u(rng), u(rng)));
  return lane;
}

void load(ContactBatch& b, const std::vector<Lane>& lanes) {
  b.size = static_cast<int>(lanes.size());
  for (int k = 0; k < b.size; ++k) {
    const ContactGeometry& g = lanes[k].g;
    b.dx[k] = g.del.x(), b.dy[k] = g.del.y(), b.dz[k] = g.del.z();
    b.rsq[k] = g.del.squaredNorm();
    b.radsum[k] = g.contact_distance, b.reff[k] = g.reff, b.meff[k] = g.meff;
    b.vx[k] = g.rel_velocity.x(), b.vy[k] = g.rel_velocity.y(), b.vz[k] = g.rel_velocity.z();
    b.wx[k] = g.spin_sum.x(), b.wy[k] = g.spin_sum.y(), b.wz[k] = g.spin_sum.z();
    b.sx[k] = lanes[k].shear.x(), b.sy[k] = lanes[k].shear.y(), b.sz[k] = lanes[k].shear.z();
  }
}

std::vector<SimdLevel> levels_this_cpu_runs() {
  std::vector<SimdLevel> levels;
  for (SimdLevel level : {SimdLevel::Baseline, SimdLevel::Avx2, SimdLevel::Avx512})
    if (level <= cpu_simd_level()) levels.push_back(level);
  return levels;
}

}  // namespace

TEST(ContactBatch, EveryVariantAgreesWithTheScalarLawOnRandomPairs) {
  std::mt19937_64 rng(7);
  ContactParams p = support::soft_params(0.5);
  const double dt = 1e-4;
  auto batch = std::make_unique<ContactBatch>();
  for (SimdLevel level : levels_this_cpu_runs()) {
    int slipping = 0, sticking = 0, unsprung_slips = 0, bitwise = 0, lanes_total = 0;
    for (int round = 0; round < 40; ++round) {
      const bool update = round % 2 == 0;
      // Sizes that leave a partial vector at the end, up to a full batch.
      const int size = 1 + (round * 13) % ContactBatch::kCapacity;
      std::vector<Lane> lanes;
      for (int k = 0; k < size; ++k) lanes.push_back(random_lane(rng, k + round));
      load(*batch, lanes);
      hertz_history_batch(p, dt, update, *batch, level);
      lanes_total += size;
      for (int k = 0; k < size; ++k) {
        Vec3 shear = lanes[k].shear;
        const PairForce want = hertz_history(p, lanes[k].g, dt, shear, update);
        const Vec3 force(batch->fx[k], batch->fy[k], batch->fz[k]);
        const Vec3 torque(batch->tx[k], batch->ty[k], batch->tz[k]);
        const Vec3 spring(batch->sx[k], batch->sy[k], batch->sz[k]);
        const double scale = want.force.norm() + 1e-300;
        ASSERT_LE((force - want.force).norm(), 1e-12 * scale) << simd_level_key(level) << " lane " << k;
        ASSERT_LE((torque - want.torque).norm(), 1e-12 * scale) << simd_level_key(level) << " lane " << k;
        // The rescaled spring is ratio (s + a) - a with a the dashpot written as a spring: its
        // rounding is relative to |a| too, which can be far larger than the result.
        const ContactGeometry& g = lanes[k].g;
        const double a = g.meff * p.gammat / p.kt * (g.rel_velocity.norm() + g.spin_sum.norm());
        ASSERT_LE((spring - shear).norm(), 1e-12 * (shear.norm() + a))
            << simd_level_key(level) << " lane " << k;
        const Vec3 tangential =
            want.force - lanes[k].g.del * (want.force.dot(lanes[k].g.del) / lanes[k].g.r / lanes[k].g.r);
        const double normal = (want.force - tangential).norm();
        const bool slips = tangential.norm() >= p.mu * normal * (1 - 1e-9);
        slipping += slips;
        sticking += !slips;
        // No spring and no update: a dashpot force above the cap is dropped, not rescaled.
        unsprung_slips += !update && lanes[k].shear.norm() == 0.0 && tangential.norm() <= 1e-12 * normal;
        bitwise += force == want.force && torque == want.torque && spring == shear;
      }
    }
    // The random states reach both sides of the Coulomb cap.
    EXPECT_GT(slipping, 100) << simd_level_key(level);
    EXPECT_GT(sticking, 100) << simd_level_key(level);
    // ... and a slip with no spring to rescale (the force is dropped, as in LAMMPS).
    EXPECT_GT(unsprung_slips, 0) << simd_level_key(level);
    std::printf("%s: %d of %d lanes bitwise equal to the scalar law\n", simd_level_key(level), bitwise,
                lanes_total);
  }
}

TEST(ContactBatch, GranudragSimdNamesTheLevelsAndRejectsOthers) {
  for (SimdLevel level : {SimdLevel::Baseline, SimdLevel::Avx2, SimdLevel::Avx512})
    EXPECT_EQ(parse_simd_level(simd_level_key(level)), level);
  try {
    parse_simd_level("sse9");
    FAIL() << "an unknown level was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("GRANUDRAG_SIMD='sse9'"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("baseline, avx2 or avx512"), std::string::npos) << e.what();
  }
  EXPECT_LE(best_simd_level(), cpu_simd_level());
}
