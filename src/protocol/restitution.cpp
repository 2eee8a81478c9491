#include "protocol/restitution.hpp"

#include <cmath>

#include "core/error.hpp"
#include "engine/simulation.hpp"

namespace granudrag {

Collision hertz_collision(double kn, double gamman, double meff, double reff, double v0) {
  const double sr = std::sqrt(reff);
  auto accel = [&](double x, double v) {
    const double xp = x > 0 ? x : 0.0;
    return -sr * std::sqrt(xp) * (kn * xp + meff * gamman * v) / meff;
  };
  const double h = hertz_collision_time(kn, meff, reff, v0) / 2.0e5;
  double x = 0, v = v0, t = 0;
  for (long step = 0; step < 100000000; ++step) {
    const double k1x = v, k1v = accel(x, v);
    const double k2x = v + 0.5 * h * k1v, k2v = accel(x + 0.5 * h * k1x, v + 0.5 * h * k1v);
    const double k3x = v + 0.5 * h * k2v, k3v = accel(x + 0.5 * h * k2x, v + 0.5 * h * k2v);
    const double k4x = v + h * k3v, k4v = accel(x + h * k3x, v + h * k3v);
    const double xn = x + h / 6 * (k1x + 2 * k2x + 2 * k3x + k4x);
    const double vn = v + h / 6 * (k1v + 2 * k2v + 2 * k3v + k4v);
    if (step > 0 && xn <= 0) {
      const double frac = x / (x - xn);
      return {-(v + frac * (vn - v)) / v0, t + frac * h};
    }
    x = xn;
    v = vn;
    t += h;
  }
  throw Error("the grain never left the wall: gamma_n = " + std::to_string(gamman) +
              " overdamps the collision at v = " + std::to_string(v0));
}

double dem_restitution(const ContactParams& c, double v, double diameter) {
  const double r = 0.5 * diameter;
  Particles p;
  p.add(Vec3(5, 5, r), r, Species::Mobile);
  p.v[0] = Vec3(0, 0, -v);
  Settings s;
  s.gravity = Vec3::Zero();
  Simulation sim(p, Box{10, 10, true}, c, s);
  const long max_steps = 100 * std::lround(hertz_collision_time(c.kn, p.mass[0], r, v) / sim.dt()) + 1000;
  for (long k = 0; k < max_steps; ++k) {
    sim.step();
    const Particles& q = sim.particles();
    if (q.x[0].z() >= r && q.v[0].z() > 0) return q.v[0].z() / v;
  }
  throw Error("the grain did not rebound from the wall within 100 collision times");
}

}  // namespace granudrag
