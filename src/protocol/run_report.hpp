#pragma once
// The end-of-run lines a pour and a pull print and record, written once so that the two read
// alike: the sanity report (CoMD style: lost grains, overlaps, energy balance, throughput) and
// the timing of the step loop by phase (miniMD / LAMMPS style).
#include <optional>
#include <string>

#include "core/timer.hpp"

namespace granudrag {

struct SanityFigures {
  long grains_lost = 0;
  long grains = 0;             // mobile ones
  double largest_overlap = 0;  // d
  double energy_start = 0;     // of the grains, rho g d^4
  double energy_end = 0;
  std::optional<double> work;  // by the intruder on the grains; none when it is held fixed
  double particle_steps_per_second = 0;
};

// "sanity: grains lost 0 of 2871; largest overlap 0.0156 d; energy of the grains E0 -> E1,
// [work by the intruder W,] dissipated W - (E1 - E0) (rho g d^4); 1.2e+07 particle-steps/s\n"
std::string sanity_line(const SanityFigures& f);

// "timing: loop S s for N steps, R particle-steps/s; integration ... s\n": `seconds` and
// `steps` of the loop alone, split by `timers`' phases.
std::string timing_line(const Timers& timers, double particles, long steps, double seconds);

}  // namespace granudrag
