#include "protocol/speed_limit.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "contact/contact_params.hpp"
#include "core/error.hpp"

namespace granudrag {

namespace {
double grain_mass(double r) { return 4.0 / 3.0 * M_PI * r * r * r; }
}  // namespace

double SpeedLimits::fastest() const { return std::min({overlap, resolution, skin}); }

double SpeedLimits::impact_overlap(double v) const {
  return std::pow(5.0 * m_large * v * v / (4.0 * kn * std::sqrt(reff_large)), 0.4);
}

double SpeedLimits::dt_for(double v) const {
  return hertz_collision_time(kn, m_small, reff_small, v) / TimeStepPolicy::steps_per_collision_min;
}

SpeedLimits speed_limits(const Bed& bed, double dt, double skin, double max_overlap) {
  const Particles& p = bed.state.particles;
  const double R = p.radius[bed.intruder];
  double rmin = p.min_radius(Species::Mobile), rmax = p.max_radius(Species::Mobile);
  if (!std::isfinite(rmin) || !std::isfinite(rmax)) rmin = rmax = 0.5;  // no mobile grain
  SpeedLimits s;
  s.kn = bed.contact.kn;
  s.m_large = grain_mass(rmax);
  s.reff_large = R * rmax / (R + rmax);
  s.m_small = grain_mass(rmin);
  s.reff_small = R * rmin / (R + rmin);
  // delta_max(V) = max_overlap solved for V.
  s.overlap =
      std::sqrt(4.0 * s.kn * std::sqrt(s.reff_large) * std::pow(max_overlap, 2.5) / (5.0 * s.m_large));
  // t_c(V) = steps * dt solved for V: t_c(V) = t_c(1) V^{-1/5}.
  const double tc1 = hertz_collision_time(s.kn, s.m_small, s.reff_small, 1.0);
  s.resolution = std::pow(tc1 / (TimeStepPolicy::steps_per_collision_min * dt), 5.0);
  s.skin = skin / (10.0 * dt);
  return s;
}

void check_pull_speed(double speed, const Bed& bed, double dt, double skin, double max_overlap) {
  const SpeedLimits s = speed_limits(bed, dt, skin, max_overlap);
  if (speed <= s.fastest()) return;
  const double D = 2 * bed.state.particles.radius[bed.intruder];
  std::ostringstream msg;
  msg.precision(4);
  msg << "'speed' = " << speed << " (Fr = " << 2.0 * speed * std::sqrt(2.0 * D) / (D + 1.0)
      << ") is too fast for this bed (kn = " << s.kn << ", dt = " << dt << ", D = " << D << "): ";
  if (speed > s.overlap)
    msg << "one impact of the intruder on a grain at rest overlaps them by " << s.impact_overlap(speed)
        << " d > max_overlap = " << max_overlap << " d; ";
  if (speed > s.resolution)
    msg << "the impact lasts " << s.dt_for(speed) * TimeStepPolicy::steps_per_collision_min << ", less than "
        << TimeStepPolicy::steps_per_collision_min << " steps of dt; ";
  if (speed > s.skin)
    msg << "the intruder moves V dt = " << speed * dt << " d per step > skin/10 = " << skin / 10 << " d; ";
  const double fastest = s.fastest();
  msg << "the largest speed that works is " << fastest
      << " (Fr = " << 2.0 * fastest * std::sqrt(2.0 * D) / (D + 1.0) << ")";
  if (speed <= s.overlap) {
    msg << ", or pour the bed with dt <= " << std::min(s.dt_for(speed), skin / (10.0 * speed));
  } else {
    msg << "; a stiffer kn (the overlap falls as kn^-2/5) or a larger 'max_overlap' allows more";
  }
  throw Error(msg.str());
}

}  // namespace granudrag
