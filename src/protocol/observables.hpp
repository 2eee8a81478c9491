#pragma once
// Statistics of a pull's time series (SPEC §4).
#include <vector>

namespace granudrag {

// Standard error of the mean of a correlated series by block averaging (Flyvbjerg & Petersen
// 1989): the series is halved by pairwise averaging until fewer than 8 blocks remain, and the
// largest standard error over those levels is returned (the plateau, or an upper bound if the
// blocks never become independent). NaN for fewer than 8 samples.
double block_average_error(const std::vector<double>& x);

// Running mean x_0, (x_0 + x_1)/2, ... (paper Fig. 4, thick line).
std::vector<double> cumulative_average(const std::vector<double>& x);

double mean(const std::vector<double>& x);

}  // namespace granudrag
