// The contact law alone: analytic limits, and an independent scalar transcription of the
// LAMMPS gran/hertz/history update (written from its published algorithm, one double at a
// time) on random pair states, agreeing to rounding (1e-10 relative: the two evaluate
// cross products in a different order, and the Coulomb rescaling cancels digits).
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "contact/contact_law.hpp"
#include "helpers.hpp"

using namespace granudrag;

namespace {

struct ScalarResult {
  double f[3], tor[3], shear[3];
};

// Reference written against the LAMMPS algorithm with plain arrays, deliberately not sharing
// any code (or Eigen) with contact_law.hpp.
ScalarResult scalar_reference(const ContactParams& p, const double del[3], double radi, double radj,
                              double meff, const double vi[3], const double vj[3], const double wi[3],
                              const double wj[3], double dt, const double shear_in[3]) {
  ScalarResult out{};
  double s[3] = {shear_in[0], shear_in[1], shear_in[2]};
  const double rsq = del[0] * del[0] + del[1] * del[1] + del[2] * del[2];
  const double r = std::sqrt(rsq), rinv = 1 / r, rsqinv = 1 / rsq;
  const double radsum = radi + radj;
  double vr[3], vt[3], wr[3], vtr[3], fs[3];
  for (int k = 0; k < 3; ++k) vr[k] = vi[k] - vj[k];
  const double vnnr = vr[0] * del[0] + vr[1] * del[1] + vr[2] * del[2];
  for (int k = 0; k < 3; ++k) vt[k] = vr[k] - del[k] * vnnr * rsqinv;
  for (int k = 0; k < 3; ++k) wr[k] = (radi * wi[k] + radj * wj[k]) * rinv;
  const double poly = std::sqrt((radsum - r) * radi * radj / radsum);
  const double ccel = poly * (p.kn * (radsum - r) * rinv - meff * p.gamman * vnnr * rsqinv);
  vtr[0] = vt[0] - (del[2] * wr[1] - del[1] * wr[2]);
  vtr[1] = vt[1] - (del[0] * wr[2] - del[2] * wr[0]);
  vtr[2] = vt[2] - (del[1] * wr[0] - del[0] * wr[1]);
  for (int k = 0; k < 3; ++k) s[k] += vtr[k] * dt;
  const double shrmag = std::sqrt(s[0] * s[0] + s[1] * s[1] + s[2] * s[2]);
  const double rsht = (s[0] * del[0] + s[1] * del[1] + s[2] * del[2]) * rsqinv;
  for (int k = 0; k < 3; ++k) s[k] -= rsht * del[k];
  for (int k = 0; k < 3; ++k) fs[k] = -poly * (p.kt * s[k] + meff * p.gammat * vtr[k]);
  const double fsm = std::sqrt(fs[0] * fs[0] + fs[1] * fs[1] + fs[2] * fs[2]);
  const double fn = p.mu * std::fabs(ccel * r);
  if (fsm > fn) {
    if (shrmag != 0) {
      for (int k = 0; k < 3; ++k) {
        const double d = meff * p.gammat * vtr[k] / p.kt;
        s[k] = (fn / fsm) * (s[k] + d) - d;
        fs[k] *= fn / fsm;
      }
    } else {
      fs[0] = fs[1] = fs[2] = 0;
    }
  }
  for (int k = 0; k < 3; ++k) out.f[k] = del[k] * ccel + fs[k];
  out.tor[0] = rinv * (del[1] * fs[2] - del[2] * fs[1]);
  out.tor[1] = rinv * (del[2] * fs[0] - del[0] * fs[2]);
  out.tor[2] = rinv * (del[0] * fs[1] - del[1] * fs[0]);
  for (int k = 0; k < 3; ++k) out.shear[k] = s[k];
  return out;
}

}  // namespace

TEST(ContactLaw, StaticOverlapGivesHertzForce) {
  ContactParams p;  // paper values
  const double ri = 0.5, rj = 0.45, delta = 1e-3;
  ContactGeometry g{Vec3(0, 0, ri + rj - delta),
                    ri + rj - delta,
                    ri + rj,
                    ri * rj / (ri + rj),
                    0.1,
                    Vec3::Zero(),
                    Vec3::Zero()};
  Vec3 shear = Vec3::Zero();
  const PairForce cf = hertz_history(p, g, 1e-5, shear);
  const double expected = p.kn * std::sqrt(g.reff * delta) * delta;  // paper Eq. 1, v_n = 0
  EXPECT_NEAR(cf.force.z(), expected, 1e-12 * expected);
  EXPECT_EQ(cf.force.x(), 0.0);
  EXPECT_EQ(cf.torque.norm(), 0.0);
}

TEST(ContactLaw, ApproachingPairIsDampedRepulsively) {
  ContactParams p;
  ContactGeometry g{Vec3(0, 0, 0.999), 0.999, 1.0, 0.25, 0.26, Vec3(0, 0, -1.0), Vec3::Zero()};
  Vec3 s1 = Vec3::Zero(), s2 = Vec3::Zero();
  const double approaching = hertz_history(p, g, 1e-5, s1).force.z();
  g.rel_velocity = Vec3(0, 0, 1.0);
  const double separating = hertz_history(p, g, 1e-5, s2).force.z();
  const double spring = p.kn * std::sqrt(0.25 * 1e-3) * 1e-3;
  const double dashpot = std::sqrt(0.25 * 1e-3) * 0.26 * p.gamman * 1.0;
  EXPECT_NEAR(approaching, spring + dashpot, 1e-9 * spring);
  EXPECT_NEAR(separating, spring - dashpot, 1e-9 * spring);
}

TEST(ContactLaw, AgreesWithScalarTranscriptionOfLammps) {
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> u(-1.0, 1.0), rad(0.45, 0.55), ov(1e-6, 2e-2);
  for (int trial = 0; trial < 2000; ++trial) {
    ContactParams p = ContactParams{}.with_stiffness(std::pow(10.0, 4 + 4 * (u(rng) + 1) / 2));
    p.mu = (trial % 4 == 0) ? 0.0 : 0.9 * (u(rng) + 1) / 2;
    const double ri = rad(rng), rj = (trial % 7 == 0) ? 2.0 : rad(rng);
    Vec3 n(u(rng), u(rng), u(rng));
    n.normalize();
    const double r = ri + rj - ov(rng);
    const Vec3 del = r * n;
    const double mi = sphere_mass(ri), mj = sphere_mass(rj), meff = mi * mj / (mi + mj);
    const Vec3 vi(u(rng), u(rng), u(rng)), vj(u(rng), u(rng), u(rng));
    const Vec3 wi = 3 * Vec3(u(rng), u(rng), u(rng)), wj = 3 * Vec3(u(rng), u(rng), u(rng));
    const Vec3 shear0 = (trial % 3 == 0) ? Vec3::Zero() : Vec3(1e-2 * Vec3(u(rng), u(rng), u(rng)));
    const double dt = 1e-4;

    ContactGeometry g{del, r, ri + rj, ri * rj / (ri + rj), meff, vi - vj, ri * wi + rj * wj};
    Vec3 shear = shear0;
    const PairForce cf = hertz_history(p, g, dt, shear);
    const ScalarResult ref = scalar_reference(p, del.data(), ri, rj, meff, vi.data(), vj.data(), wi.data(),
                                              wj.data(), dt, shear0.data());
    const double fscale = Vec3(ref.f[0], ref.f[1], ref.f[2]).norm() + 1e-300;
    for (int k = 0; k < 3; ++k) {
      ASSERT_NEAR(cf.force[k], ref.f[k], 1e-10 * fscale) << "trial " << trial;
      ASSERT_NEAR(cf.torque[k], ref.tor[k], 1e-10 * fscale) << "trial " << trial;
      ASSERT_NEAR(shear[k], ref.shear[k], 1e-10 * (shear0.norm() + 1e-3)) << "trial " << trial;
    }
  }
}

TEST(ContactLaw, CoulombCapRewritesSpringToMatchCap) {
  ContactParams p;
  p.mu = 0.3;
  const double r = 0.998;
  ContactGeometry g{Vec3(0, 0, r), r, 1.0, 0.25, 0.26, Vec3(0.2, 0, 0), Vec3::Zero()};
  Vec3 shear(0.05, 0.0, 0.0);  // far beyond the sliding threshold
  const PairForce cf = hertz_history(p, g, 1e-5, shear);
  const double fn = cf.force.z();
  const Vec3 ft(cf.force.x(), cf.force.y(), 0.0);
  EXPECT_NEAR(ft.norm(), p.mu * std::abs(fn), 1e-12 * std::abs(fn));
  EXPECT_LT(ft.x(), 0.0);  // opposes the sliding direction
  // The rewritten spring plus the dashpot reproduce the capped force exactly.
  const double poly = std::sqrt((1.0 - r) * 0.25);
  const Vec3 regenerated = -poly * (p.kt * shear + g.meff * p.gammat * Vec3(0.2, 0, 0));
  EXPECT_NEAR((regenerated - ft).norm(), 0.0, 1e-12 * ft.norm());
}

TEST(ContactLaw, SpringStaysInTangentPlane) {
  ContactParams p;
  Vec3 n(1, 2, 3);
  n.normalize();
  ContactGeometry g{0.999 * n, 0.999, 1.0, 0.25, 0.26, Vec3(0.3, -0.1, 0.2), Vec3(0.1, 0.4, -0.2)};
  Vec3 shear(1e-4, 2e-4, -3e-4);  // has a normal part to be projected away
  hertz_history(p, g, 1e-5, shear);
  EXPECT_NEAR(shear.dot(n), 0.0, 1e-18);
}

TEST(ContactLaw, FrozenPartnerGivesMobileMass) {
  EXPECT_EQ(effective_mass(2.0, Species::Frozen, 0.5, Species::Mobile), 0.5);
  EXPECT_EQ(effective_mass(2.0, Species::Mobile, 0.5, Species::Frozen), 2.0);
  EXPECT_DOUBLE_EQ(effective_mass(2.0, Species::Mobile, 0.5, Species::Intruder), 0.4);
}

TEST(ContactParams, YoungsModulusFormOfEq3) {
  const ContactParams p = ContactParams::from_young(1000.0, 0.3, 1.0, 2.0, 0.4);
  const double G = 1000.0 / 2.6;
  EXPECT_DOUBLE_EQ(p.kn, 4 * G / (3 * 0.7));
  EXPECT_DOUBLE_EQ(p.kt, 4 * G / 1.7);
  EXPECT_EQ(p.gammat, 2.0);
  // Out of their key rows' ranges (contact_keys.cpp), each named, both in one message.
  try {
    ContactParams::from_young(-1, 0.6, 1, 1, 0.5);
    ADD_FAILURE() << "from_young accepted E = -1, nu = 0.6";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("youngs_modulus"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("poisson_ratio"), std::string::npos) << e.what();
  }
  EXPECT_THROW(ContactParams::from_young(std::nan(""), 0.3, 1, 1, 0.5), Error);
  EXPECT_THROW(ContactParams::from_young(1, -1, 1, 1, 0.5), Error);
  EXPECT_NO_THROW(ContactParams::from_young(1, 0.49, 1, 1, 0.5));
}

TEST(ContactParams, SofterVariantKeepsRestitutionInvariants) {
  const ContactParams paper;
  const ContactParams soft = paper.with_stiffness(2e5);
  EXPECT_DOUBLE_EQ(soft.kt / soft.kn, paper.kt / paper.kn);
  EXPECT_NEAR(soft.gamman / std::pow(soft.kn, 0.6), paper.gamman / std::pow(paper.kn, 0.6), 1e-12);
  EXPECT_DOUBLE_EQ(soft.gammat / soft.gamman, paper.gammat / paper.gamman);
}

TEST(ContactParams, RejectsOutOfRangeWithKeyName) {
  ContactParams p;
  p.mu = -0.1;
  try {
    p.validate();
    FAIL() << "mu < 0 accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("'mu'"), std::string::npos) << e.what();
  }
  p = ContactParams{};
  p.kn = 0;
  EXPECT_THROW(p.validate(), Error);
}
