#pragma once
// A progress line on stderr for long loops: done/total, rate and ETA, at most every few seconds.
#include <omp.h>

#include <cstdio>
#include <string>

namespace granudrag {

class Progress {
 public:
  Progress(std::string label, long total, double interval_seconds = 5.0)
      : label_(std::move(label)),
        total_(total),
        interval_(interval_seconds),
        t0_(omp_get_wtime()),
        last_(t0_) {}
  void update(long done, double work_per_item = 1.0, const char* unit = "steps") {
    const double now = omp_get_wtime();
    if (now - last_ < interval_ && done < total_) return;
    last_ = now;
    const double elapsed = now - t0_;
    const double rate = elapsed > 0 ? done / elapsed : 0.0;
    const double eta = rate > 0 ? (total_ - done) / rate : 0.0;
    std::fprintf(stderr, "%s: %ld/%ld (%.0f%%), %.3g %s/s, elapsed %.0f s, ETA %.0f s\n", label_.c_str(),
                 done, total_, 100.0 * done / (total_ > 0 ? total_ : 1), rate * work_per_item, unit, elapsed,
                 eta);
  }

 private:
  std::string label_;
  long total_;
  double interval_, t0_, last_;
};

}  // namespace granudrag
