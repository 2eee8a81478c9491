#pragma once
// The Hertz contact law with tangential history, exactly as LAMMPS `pair gran/hertz/history`
// and `fix wall/gran hertz/history` (paper Eqs. 1-2):
//   F_n = sqrt(R_eff delta) (K_n delta - m_eff gamma_n v_n)            along n
//   F_t = -min(mu |F_n|, |sqrt(R_eff delta)(K_t s + m_eff gamma_t v_t)|) along the trial force
// A pure function of the pair's geometry, velocities and history: testable alone, shared by
// the fast path, the brute-force oracle and the wall.
#include <cmath>

#include "contact/contact_params.hpp"
#include "core/particles.hpp"
#include "core/vec3.hpp"

namespace granudrag {

struct PairForce {
  Vec3 force;   // on body i; body j gets -force
  Vec3 torque;  // lever-free part: torque on i is -R_i * torque, on j is -R_j * torque
};

// Both bodies' state for one contact. For the wall, j is the wall: contact_distance = R_i,
// reff = R_i, meff = m_i, and rel_velocity / spin_sum use the wall at rest.
struct ContactGeometry {
  Vec3 del;                 // r_i - r_j (minimum image); for the wall (0, 0, z_i)
  double r;                 // |del|, strictly less than contact_distance
  double contact_distance;  // R_i + R_j
  double reff;              // R_i R_j / (R_i + R_j)
  double meff;              // m_i m_j / (m_i + m_j), or the mobile partner's mass (frozen, wall)
  Vec3 rel_velocity;        // v_i - v_j
  Vec3 spin_sum;            // R_i w_i + R_j w_j
};

// m_eff: a frozen grain counts as infinitely heavy (LAMMPS fix freeze); the intruder has its
// own mass rho*pi*D^3/6 because it is driven, not integrated.
inline double effective_mass(double mi, Species ki, double mj, Species kj) {
  if (ki == Species::Frozen) return mj;
  if (kj == Species::Frozen) return mi;
  return mi * mj / (mi + mj);
}

// shear: the pair's tangential spring, updated in place (accumulated, projected onto the
// tangent plane, rescaled at the Coulomb cap). update_history = false only for the force
// evaluation of a run's setup, as LAMMPS does.
inline PairForce hertz_history(const ContactParams& p, const ContactGeometry& g, double dt, Vec3& shear,
                               bool update_history = true) {
  const double rinv = 1.0 / g.r;
  const double rsqinv = rinv * rinv;
  const double delta = g.contact_distance - g.r;

  const double vnnr = g.rel_velocity.dot(g.del);
  const Vec3 vt = g.rel_velocity - g.del * (vnnr * rsqinv);
  const Vec3 vtr = vt + g.del.cross(g.spin_sum) * rinv;  // tangential velocity at the contact

  const double polyhertz = std::sqrt(delta * g.reff);
  const double ccel = polyhertz * (p.kn * delta * rinv - g.meff * p.gamman * vnnr * rsqinv);

  if (update_history) shear += vtr * dt;
  const double shrmag = shear.norm();
  if (update_history) shear -= g.del * (shear.dot(g.del) * rsqinv);

  Vec3 fs = -polyhertz * (p.kt * shear + (g.meff * p.gammat) * vtr);
  const double fs_mag = fs.norm();
  const double fn_cap = p.mu * std::abs(ccel * g.r);  // mu |F_n| with the damped F_n
  if (fs_mag > fn_cap) {
    if (shrmag != 0.0) {
      // Rewrite the spring so that spring + dashpot equal the cap exactly.
      const double ratio = fn_cap / fs_mag;
      const Vec3 dashpot_as_spring = vtr * (g.meff * p.gammat / p.kt);
      shear = ratio * (shear + dashpot_as_spring) - dashpot_as_spring;
      fs *= ratio;
    } else {
      fs.setZero();
    }
  }
  return {g.del * ccel + fs, g.del.cross(fs) * rinv};
}

// Elastic energy stored in the normal spring: integral of K_n sqrt(R_eff) delta^{3/2}.
inline double hertz_normal_energy(double kn, double reff, double delta) {
  return 0.4 * kn * std::sqrt(reff) * delta * delta * std::sqrt(delta);
}

}  // namespace granudrag
