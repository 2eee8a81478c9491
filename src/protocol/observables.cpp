#include "protocol/observables.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace granudrag {

double mean(const std::vector<double>& x) {
  if (x.empty()) return NAN;
  return std::accumulate(x.begin(), x.end(), 0.0) / static_cast<double>(x.size());
}

double block_average_error(const std::vector<double>& series) {
  if (series.size() < 8) return NAN;
  std::vector<double> x = series;
  double best = 0.0;
  while (x.size() >= 8) {
    const double m = mean(x);
    double var = 0;
    for (double v : x) var += (v - m) * (v - m);
    var /= static_cast<double>(x.size() - 1);
    best = std::max(best, std::sqrt(var / static_cast<double>(x.size())));
    std::vector<double> halved(x.size() / 2);
    for (std::size_t k = 0; k < halved.size(); ++k) halved[k] = 0.5 * (x[2 * k] + x[2 * k + 1]);
    x.swap(halved);
  }
  return best;
}

std::vector<double> cumulative_average(const std::vector<double>& x) {
  std::vector<double> out(x.size());
  double sum = 0;
  for (std::size_t k = 0; k < x.size(); ++k) {
    sum += x[k];
    out[k] = sum / static_cast<double>(k + 1);
  }
  return out;
}

}  // namespace granudrag
