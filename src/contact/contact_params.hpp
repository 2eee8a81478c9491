#pragma once
// Contact-law parameters (paper Eqs. 1-3) in units of rho, d and g:
// K_n, K_t in rho*d*g; gamma_n, gamma_t in sqrt(g/d^3); mu dimensionless.
#include <string>

namespace granudrag {

struct ContactParams {
  double kn = 2.0e8;
  double kt = 2.45e8;
  double gamman = 5.0e4;
  double gammat = 5.0e4;
  double mu = 0.5;

  // Eq. 3: G = E/(2(1+nu)), K_n = 4G/(3(1-nu)), K_t = 4G/(2-nu).
  static ContactParams from_young(double youngs_modulus, double poisson_ratio, double gamman, double gammat,
                                  double mu);

  // A softer (or stiffer) variant with the same restitution curve: K_t/K_n, gamma_t/gamma_n
  // and gamma_n/K_n^0.6 held fixed (paper Sec. III I).
  ContactParams with_stiffness(double kn_new) const;

  // Throws granudrag::Error naming the offending parameter and its allowed range.
  void validate() const;
  std::string describe() const;
};

// Duration of an undamped Hertz collision m x'' = -k x^{3/2} with k = K_n sqrt(R_eff), at
// impact speed v: t_c = 2.9432 (5 m / (4 k))^{2/5} v^{-1/5}.
double hertz_collision_time(double kn, double meff, double reff, double impact_speed);

// The time-step policy. The shortest collision is between two of the smallest grains at the
// fastest speed of the study (v_ref = 10 sqrt(g d)); with the paper's K_n = 2e8 and d_min = 0.9
// it is t_c = 6.8e-4, and the paper's dt = 1e-5 is t_c/68.
struct TimeStepPolicy {
  static constexpr double reference_speed = 10.0;
  static constexpr double steps_per_collision_default = 64.0;  // dt when none is given
  static constexpr double steps_per_collision_min = 16.0;      // refused below this
};

double shortest_collision_time(const ContactParams& p, double min_radius);
double default_time_step(const ContactParams& p, double min_radius);
// Throws granudrag::Error, stating a time step that would do, when dt is too large.
void check_time_step(double dt, const ContactParams& p, double min_radius);

}  // namespace granudrag
