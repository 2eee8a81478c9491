#pragma once
// A progress line on stderr for long loops: done/total, rate and ETA, at most every few seconds.
#include <omp.h>

#include <cstdio>
#include <string>

namespace granudrag {

class Progress {
 public:
  // `first`: items done before this run (a resumed pull or pour), left out of the rate so that it
  // and the ETA are this run's, not the run's since its first start.
  Progress(std::string label, long total, long first = 0, double interval_seconds = 5.0)
      : label_(std::move(label)),
        total_(total),
        first_(first),
        interval_(interval_seconds),
        t0_(omp_get_wtime()),
        last_(t0_) {}
  void update(long done, double work_per_item = 1.0, const char* unit = "steps") {
    const double now = omp_get_wtime();
    if (now - last_ < interval_ && done < total_) return;
    last_ = now;
    std::fprintf(stderr, "%s\n", line(done, now - t0_, work_per_item, unit).c_str());
  }
  // The line after `elapsed` seconds of this run, with `done` of the total done in all.
  std::string line(long done, double elapsed, double work_per_item = 1.0, const char* unit = "steps") const {
    const double rate = elapsed > 0 ? static_cast<double>(done - first_) / elapsed : 0.0;
    const double eta = rate > 0 ? static_cast<double>(total_ - done) / rate : 0.0;
    char buf[256];
    std::snprintf(buf, sizeof buf, "%s: %ld/%ld (%.0f%%), %.3g %s/s, elapsed %.0f s, ETA %.0f s",
                  label_.c_str(), done, total_,
                  100.0 * static_cast<double>(done) / static_cast<double>(total_ > 0 ? total_ : 1),
                  rate * work_per_item, unit, elapsed, eta);
    return buf;
  }

 private:
  std::string label_;
  long total_, first_;
  double interval_, t0_, last_;
};

}  // namespace granudrag
