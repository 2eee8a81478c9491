#pragma once
// Statistics of a pull's time series (the drag, n, theta and Z of the paper's Sec. III).
#include <vector>

namespace granudrag {

// The mean of a correlated series and its standard error, honest down to a few correlation
// times of data (see observables.cpp for the method and its measured coverage).
struct MeanError {
  double mean = 0.0 / 0.0;
  double error = 0.0 / 0.0;  // standard error of the mean
  double dof = 0.0 / 0.0;    // effective degrees of freedom of `error`: quote mean +- t_dof * error
  long window = 0;           // summation window of the autocorrelation, samples
  bool plateau = false;      // the error is converged (see observables.cpp); else a conservative bound
};

// NaN error for fewer than 8 samples.
MeanError mean_error(const std::vector<double>& x);

// The ratio sum(s)/sum(c) of a series of per-sample sums s_k of counted items and their counts
// c_k (the contact angles formed in each sample interval), and its standard error. Items of one
// sample, and of neighbouring samples, are not independent (a grain chattering on the intruder
// forms a contact at one angle many times), so the error is not the items' sd / sqrt(count): it
// is mean_error of the linearized series (s_k - r c_k) / mean(c) (the delta method), which
// carries their correlations. NaN for fewer than 8 samples or no items.
MeanError ratio_error(const std::vector<double>& sums, const std::vector<double>& counts);

// The standard error of mean_error (kept for callers that want the number only).
double block_average_error(const std::vector<double>& x);

// The mean and error of growing prefixes of a series: the first 8 samples, then about sqrt(2)
// times more each time (8, 11, 16, 23, 32, ...), and the whole series last. How the drag and its
// error converge with the travel of a pull (the pull-length validation reads it).
struct PrefixError {
  long samples = 0;
  MeanError estimate;
};
std::vector<PrefixError> prefix_errors(const std::vector<double>& x);

// Quantile of Student's t distribution with nu >= 1 (real) degrees of freedom, 0 < p < 1.
double student_t_quantile(double p, double nu);

// Running mean x_0, (x_0 + x_1)/2, ... (paper Fig. 4, thick line).
std::vector<double> cumulative_average(const std::vector<double>& x);

double mean(const std::vector<double>& x);

}  // namespace granudrag
