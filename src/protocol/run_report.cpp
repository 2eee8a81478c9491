#include "protocol/run_report.hpp"

#include <algorithm>
#include <sstream>

namespace granudrag {

std::string sanity_line(const SanityFigures& f) {
  std::ostringstream s;
  s << "sanity: grains lost " << f.grains_lost << " of " << f.grains << "; largest overlap "
    << f.largest_overlap << " d; energy of the grains " << f.energy_start << " -> " << f.energy_end;
  if (f.work) s << ", work by the intruder " << *f.work;
  s << ", dissipated " << f.work.value_or(0.0) - (f.energy_end - f.energy_start) << " (rho g d^4); "
    << f.particle_steps_per_second << " particle-steps/s\n";
  return s.str();
}

std::string timing_line(const Timers& t, double particles, long steps, double seconds) {
  std::ostringstream s;
  s << "timing: loop " << seconds << " s for " << steps << " steps, "
    << particles * steps / std::max(seconds, 1e-9) << " particle-steps/s;";
  for (int k = 0; k < static_cast<int>(Phase::Count); ++k)
    s << ' ' << phase_name(static_cast<Phase>(k)) << ' ' << t.seconds(static_cast<Phase>(k));
  s << " s\n";
  return s.str();
}

}  // namespace granudrag
