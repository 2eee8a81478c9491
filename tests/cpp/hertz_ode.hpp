#pragma once
// The independent answer for a single normal collision: the two-body viscoelastic Hertz
// equation  m x'' = -sqrt(R x) (K_n x + m gamma_n x')  (x the overlap), integrated by
// classical RK4 with ~2e5 steps per collision, the end of contact located by interpolation.
#include <cmath>

namespace granudrag::support {

struct CollisionResult {
  double restitution;  // -x'(end) / x'(0)
  double duration;
};

inline CollisionResult integrate_hertz_collision(double kn, double gamman, double meff,
                                                 double reff, double v0) {
  const double sr = std::sqrt(reff);
  auto accel = [&](double x, double v) {
    const double xp = x > 0 ? x : 0.0;
    return -sr * std::sqrt(xp) * (kn * xp + meff * gamman * v) / meff;
  };
  // Undamped duration sets the step: t_c = 2.9432 (5 m / 4 k)^{2/5} v^{-1/5}.
  const double tc = 2.9432 * std::pow(5 * meff / (4 * kn * sr), 0.4) * std::pow(v0, -0.2);
  const double h = tc / 2.0e5;
  double x = 0, v = v0, t = 0;
  for (long step = 0; step < 100000000; ++step) {
    const double k1x = v, k1v = accel(x, v);
    const double k2x = v + 0.5 * h * k1v, k2v = accel(x + 0.5 * h * k1x, v + 0.5 * h * k1v);
    const double k3x = v + 0.5 * h * k2v, k3v = accel(x + 0.5 * h * k2x, v + 0.5 * h * k2v);
    const double k4x = v + h * k3v, k4v = accel(x + h * k3x, v + h * k3v);
    const double xn = x + h / 6 * (k1x + 2 * k2x + 2 * k3x + k4x);
    const double vn = v + h / 6 * (k1v + 2 * k2v + 2 * k3v + k4v);
    if (step > 0 && xn <= 0) {
      const double frac = x / (x - xn);  // linear interpolation of the zero crossing
      return {-(v + frac * (vn - v)) / v0, t + frac * h};
    }
    x = xn;
    v = vn;
    t += h;
  }
  return {NAN, NAN};
}

}  // namespace granudrag::support
