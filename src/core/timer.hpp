#pragma once
// Wall-clock time per phase of the step loop (the miniMD / LAMMPS "loop time" breakdown). One
// omp_get_wtime() per phase boundary, a few per step: off the hot loops.
#include <omp.h>

#include <array>

namespace granudrag {

enum class Phase {
  Integrate = 0,  // the two velocity-Verlet halves
  Neighbor,       // deciding whether to rebuild, and the rebuild of the pair lists
  History,        // carrying the tangential springs over to a rebuilt list
  Force,          // pair, intruder, wall forces and gravity
  Observables,    // what a protocol measures from the state (drag, contacts, energies)
  IO,             // checkpoints and other files written during the loop
  Other,
  Count
};
inline const char* phase_name(Phase p) {
  static const char* names[] = {"integration", "neighbour", "history", "forces",
                                "observables", "I/O",       "other"};
  return names[static_cast<int>(p)];
}

class Timers {
 public:
  void start() { last_ = omp_get_wtime(); }
  // Charges the time since the previous stamp to `phase`.
  void stamp(Phase phase) {
    const double now = omp_get_wtime();
    seconds_[static_cast<int>(phase)] += now - last_;
    last_ = now;
  }
  double seconds(Phase phase) const { return seconds_[static_cast<int>(phase)]; }
  double total() const {
    double t = 0;
    for (double s : seconds_) t += s;
    return t;
  }
  void reset() { seconds_.fill(0.0); }

 private:
  std::array<double, static_cast<int>(Phase::Count)> seconds_{};
  double last_ = 0;
};

}  // namespace granudrag
