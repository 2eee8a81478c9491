#include "contact/contact_params.hpp"

#include <cmath>
#include <sstream>

#include "contact/contact_keys.hpp"
#include "core/error.hpp"

namespace granudrag {

ContactParams ContactParams::from_young(double E, double nu, double gamman, double gammat, double mu) {
  // E and nu are keys without a field (the struct keeps kn and kt): checked against their rows.
  check_ranges(contact_keys().specs(), {{"youngs_modulus", E}, {"poisson_ratio", nu}}, "contact law");
  const double G = E / (2.0 * (1.0 + nu));
  ContactParams p;
  p.kn = 4.0 * G / (3.0 * (1.0 - nu));
  p.kt = 4.0 * G / (2.0 - nu);
  p.gamman = gamman;
  p.gammat = gammat;
  p.mu = mu;
  return p;
}

ContactParams ContactParams::with_stiffness(double kn_new) const {
  ContactParams p = *this;
  const double s = kn_new / kn;
  p.kn = kn_new;
  p.kt = kt * s;
  p.gamman = gamman * std::pow(s, 0.6);
  p.gammat = gammat * std::pow(s, 0.6);
  return p;
}

// Each field within its key's range (contact_keys.cpp).
void ContactParams::validate() const { contact_keys().check(*this, "contact law"); }

// Every field, by its key (contact_keys.cpp).
std::string ContactParams::describe() const {
  std::ostringstream s;
  for (const auto& [key, value] : contact_fields(*this))
    s << (s.tellp() > 0 ? " " : "") << key << "=" << value;
  return s.str();
}

double hertz_collision_time(double kn, double meff, double reff, double v) {
  const double k = kn * std::sqrt(reff);
  return 2.9432 * std::pow(5.0 * meff / (4.0 * k), 0.4) * std::pow(v, -0.2);
}

double shortest_collision_time(const ContactParams& p, double min_radius) {
  const double m = 4.0 / 3.0 * M_PI * min_radius * min_radius * min_radius;
  return hertz_collision_time(p.kn, 0.5 * m, 0.5 * min_radius, TimeStepPolicy::reference_speed);
}

double default_time_step(const ContactParams& p, double min_radius) {
  return shortest_collision_time(p, min_radius) / TimeStepPolicy::steps_per_collision_default;
}

void check_time_step(double dt, const ContactParams& p, double min_radius) {
  const double tc = shortest_collision_time(p, min_radius);
  const double dt_max = tc / TimeStepPolicy::steps_per_collision_min;
  if (std::isfinite(dt) && dt > 0 && dt <= dt_max) return;
  std::ostringstream msg;
  msg << "time step dt = " << dt << " is ";
  if (!(dt > 0) || !std::isfinite(dt))
    msg << "not a positive number";
  else
    msg << "too large for kn = " << p.kn << ": two grains of diameter " << 2 * min_radius << " colliding at "
        << TimeStepPolicy::reference_speed << " sqrt(gd) stay in contact for t_c = " << tc
        << ", and dt must resolve it with at least " << TimeStepPolicy::steps_per_collision_min << " steps";
  msg << ". Use dt <= " << dt_max << " (recommended: " << default_time_step(p, min_radius)
      << ", or leave dt unset to get it).";
  throw Error(msg.str());
}

}  // namespace granudrag
