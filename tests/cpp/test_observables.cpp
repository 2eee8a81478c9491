// Statistics of a pull's time series (protocol/observables.hpp): Student's t quantiles, the
// error of the mean of correlated series and the coverage of its 95 % intervals (synthetic AR(1)
// and AR(2) series, and recorded drag series), the error of a ratio of sums (theta), prefix errors and the
// running mean; and the rings of the nested coordination shells (protocol/coordination_shells.hpp). No pull
// is run here; the pulls are in test_pull.cpp.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "io/h5_file.hpp"
#include "protocol/coordination_shells.hpp"
#include "protocol/observables.hpp"

using namespace granudrag;

namespace {

std::vector<double> ar1(long n, double a, std::mt19937_64& rng) {
  std::normal_distribution<double> g(0.0, 1.0);
  std::vector<double> x(n);
  double prev = g(rng) / std::sqrt(1 - a * a);  // stationary start
  for (long k = 0; k < n; ++k) x[k] = prev = k ? a * prev + g(rng) : prev;
  return x;
}

// Fraction of nominal 95 % Student-t intervals, mean +- t(0.975, dof) error, holding `truth`.
template <class Draw>
double coverage(Draw draw, double truth, int repeats) {
  int hit = 0;
  for (int r = 0; r < repeats; ++r) {
    const MeanError e = mean_error(draw());
    if (std::abs(e.mean - truth) <= student_t_quantile(0.975, e.dof) * e.error) ++hit;
  }
  return static_cast<double>(hit) / repeats;
}

}  // namespace

TEST(Observables, StudentTQuantileMatchesTables) {
  // Tabulated t_{0.975}: nu = 1, 2, 3, 10, 30, and the normal limit.
  EXPECT_NEAR(student_t_quantile(0.975, 1), 12.706, 2e-3);
  EXPECT_NEAR(student_t_quantile(0.975, 2), 4.303, 1e-3);
  EXPECT_NEAR(student_t_quantile(0.975, 3), 3.182, 1e-3);
  EXPECT_NEAR(student_t_quantile(0.975, 10), 2.228, 1e-3);
  EXPECT_NEAR(student_t_quantile(0.975, 30), 2.042, 1e-3);
  EXPECT_NEAR(student_t_quantile(0.975, 1e5), 1.960, 1e-3);
  EXPECT_NEAR(student_t_quantile(0.025, 10), -2.228, 1e-3);
}

TEST(Observables, ErrorOfCorrelatedDataConvergesOnLongSeries) {
  // AR(1) x_k = a x_{k-1} + noise: the variance of the mean of M samples is
  // sigma_x^2/M (1 + a)/(1 - a) for M >> 1/(1 - a).
  const double a = 0.9;
  const long M = 1 << 16;
  std::mt19937_64 rng(3);
  const std::vector<double> x = ar1(M, a, rng);
  const double var_x = 1 / (1 - a * a);
  const double expected = std::sqrt(var_x / M * (1 + a) / (1 - a));
  const MeanError e = mean_error(x);
  EXPECT_NEAR(e.error, expected, 0.1 * expected);
  EXPECT_GT(e.error, 3 * std::sqrt(var_x / M));  // correlations must not be ignored
  EXPECT_TRUE(e.plateau);
  EXPECT_GT(e.dof, 100);
  EXPECT_TRUE(std::isnan(mean_error({1, 2, 3}).error));
  const MeanError flat = mean_error(std::vector<double>(20, 2.5));
  EXPECT_EQ(flat.mean, 2.5);
  EXPECT_EQ(flat.error, 0.0);
}

// AR(2) with complex roots r exp(+-i omega): a damped oscillation of period 2 pi/omega, the
// shape of a drag series' autocorrelation. Started from zero after a burn-in of 50 periods.
std::vector<double> ar2(long n, double r, double omega, std::mt19937_64& rng) {
  std::normal_distribution<double> noise;
  const double p1 = 2 * r * std::cos(omega), p2 = -r * r;
  const long burn = static_cast<long>(50 * 2 * M_PI / omega);
  std::vector<double> x;
  double x1 = 0, x2 = 0;
  for (long k = 0; k < burn + n; ++k) {
    const double xk = p1 * x1 + p2 * x2 + noise(rng);
    x2 = x1, x1 = xk;
    if (k >= burn) x.push_back(xk);
  }
  return x;
}

TEST(Observables, AnOscillatingAutocorrelationIsIntegratedThroughItsNegativeLobe) {
  // Period 100 samples, decay 40: the automatic window stops near the first zero (~30), where
  // the partial sums of the autocorrelation peak. Analytic: Var(mean) = 1/(N (1 - p1 - p2)^2).
  const double r = std::exp(-1.0 / 40), omega = 2 * M_PI / 100;
  const double p1 = 2 * r * std::cos(omega), p2 = -r * r;
  std::mt19937_64 rng(17);
  const long M = 1 << 16;
  const double expected = 1 / (std::sqrt(static_cast<double>(M)) * (1 - p1 - p2));
  double sum_sq = 0;
  const int series = 8;
  for (int k = 0; k < series; ++k) {
    const MeanError e = mean_error(ar2(M, r, omega, rng));
    EXPECT_TRUE(e.plateau);
    EXPECT_GT(e.window, 60);  // past the lobe's deepest point; the automatic window stops near 30
    sum_sq += e.error * e.error;
  }
  // 8 series of 655 periods: the rms error within 10 % of the analytic one.
  EXPECT_NEAR(std::sqrt(sum_sq / series), expected, 0.1 * expected);
  for (long n : {256L, 1024L}) {
    const double c = coverage([&] { return ar2(n, r, omega, rng); }, 0.0, 400);
    std::printf("AR(2), period 100, %ld samples: coverage %.3f\n", n, c);
    EXPECT_GE(c, 0.90) << n << " samples";
    EXPECT_LE(c, 0.98) << n << " samples";
  }
}

TEST(Observables, NinetyFivePercentIntervalsCoverAr1AtShortLengths) {
  // Correlation time 10 samples (a = exp(-1/10), tau_int = 10): at 64 samples a series has
  // about 3 independent samples. The old largest-over-block-levels error covered ~70 % there.
  const double a = std::exp(-0.1);
  std::mt19937_64 rng(11);
  for (long n : {64L, 128L, 256L, 1024L}) {
    const double c = coverage([&] { return ar1(n, a, rng); }, 0.0, 400);
    std::printf("AR(1), tau 10, %ld samples: coverage %.3f\n", n, c);
    EXPECT_GE(c, 0.90) << n << " samples";
    EXPECT_LE(c, 0.98) << n << " samples";
  }
  // No plateau at 64 samples, one at 1024 (relative error of the error <= 25 %).
  EXPECT_FALSE(mean_error(ar1(64, a, rng)).plateau);
  int plateaus = 0;
  for (int r = 0; r < 50; ++r) plateaus += mean_error(ar1(1024, a, rng)).plateau;
  EXPECT_GE(plateaus, 40);
}

// The coverage of mean_error's 95 % intervals over every disjoint window of n samples of a
// recorded set of drag series (tests/data/make_drag_series.sh: one pull each, each through its
// own bed). Windows of different pulls are independent, and disjoint windows of one pull nearly
// so (the correlation time, a few samples, is short beside n). The truth of a window is its
// pull's mean (the beds differ: their drags scatter by ~5 %). A window is part of that mean, so
// mean_w - mean_pull has the variance Var(mean_w)(1 - n/N) for n much longer than the correlation
// time; the deviation is divided by sqrt(1 - n/N) to put it back on the window mean's own scale
// (without it, 1,024 samples would cover ~1 % too often). Expects the 90-98 % band of the
// synthetic tests, widened by twice the sampling error a coverage on the band's edge would have
// over the repeats (binomial): a coverage beyond that is off the band, not unlucky.
void expect_recorded_coverage(const std::string& name, long min_length, long min_series, long min_repeats) {
  const std::string path =
      std::string(__FILE__).substr(0, std::string(__FILE__).rfind('/')) + "/../data/" + name;
  const h5::File file = h5::File::open(path);
  const std::vector<double> all = file.read_doubles("/drag");
  const long length = file.get_attr_int64("/drag", "series_length");
  ASSERT_GT(length, min_length);
  ASSERT_EQ(all.size() % length, 0u);
  const long series = static_cast<long>(all.size()) / length;
  ASSERT_GE(series, min_series);
  for (long n : {64L, 128L, 256L, 1024L}) {
    long hit = 0, repeats = 0;
    for (long s = 0; s < series; ++s) {
      const auto first = all.begin() + s * length;
      const double truth = mean(std::vector<double>(first, first + length));
      const double shrink = std::sqrt(1.0 - static_cast<double>(n) / static_cast<double>(length));
      for (long w = 0; (w + 1) * n <= length; ++w, ++repeats) {
        const MeanError e = mean_error(std::vector<double>(first + w * n, first + (w + 1) * n));
        hit += std::abs(e.mean - truth) / shrink <= student_t_quantile(0.975, e.dof) * e.error;
      }
    }
    const double c = static_cast<double>(hit) / static_cast<double>(repeats);
    const double k = static_cast<double>(repeats);
    const double low = 0.90 - 2 * std::sqrt(0.90 * 0.10 / k), high = 0.98 + 2 * std::sqrt(0.98 * 0.02 / k);
    std::printf("%s, %ld samples: coverage %.3f of %ld repeats (band %.3f-%.3f)\n", name.c_str(), n, c,
                repeats, low, high);
    EXPECT_GE(repeats, min_repeats) << n << " samples";
    EXPECT_GE(c, low) << n << " samples";
    EXPECT_LE(c, high) << n << " samples";
  }
}

TEST(Observables, NinetyFivePercentIntervalsCoverRealForceSeries) {
  // The two sets the estimator was chosen on. 48 series at D = 2, V = 1, mu = 0.5, about 9,900
  // samples each; their autocorrelation crosses 0 near 28 samples and has a negative lobe near
  // 50, the shape mean_error's step (5) is for: 432 (n = 1,024) to 7,440 (n = 64) repeats, a
  // coverage's binomial standard error 0.010 to 0.003. Measured with the N/5 fallback window
  // 0.935, 0.984, 0.956, 0.986 (N/7: 0.890 at 64 samples, N/6: 0.909).
  expect_recorded_coverage("drag_series_D2_V1_mu0.5.h5", 9000, 40, 400);
  // 40 series at D = 3, V = 0.5, mu = 0 (a frictionless bed at Fr = 0.29, a sample every 0.01 d
  // of travel instead of 0.02 d), 7,442 samples each: 280 to 4,640 repeats. Recorded to hold
  // out N/6, which covered 0.882 at 64 samples, below the band; N/5, chosen then: 0.905,
  // 0.966, 0.966, 0.968.
  expect_recorded_coverage("drag_series_D3_V0.5_mu0.h5", 7000, 40, 250);
}

TEST(Observables, NinetyFivePercentIntervalsCoverHeldOutForceSeries) {
  // Held out: 40 series at yet another D, V and mu (D = 1, V = 2, mu = 0.25: Fr = 2, a sample
  // every 0.04 d of travel), recorded after the N/5 window was chosen and used to choose
  // nothing. Measured 0.969, 0.982, 0.968, 0.961 (N/6: 0.964, 0.981, 0.968, 0.961; this set
  // alone would not have told the two apart; the independent-sample error,
  // the naive estimator: 0.477, 0.578, 0.628, 0.679).
  expect_recorded_coverage("drag_series_D1_V2_mu0.25.h5", 7000, 40, 250);
}

TEST(Observables, AnAnticorrelatedShortSeriesGetsItsIndependentSampleErrorNotZero) {
  // Two periods of +1, +1, -1, -1: the autocovariances 1, 1/7, -1, ... sum to a negative window.
  // Before, the error was 0.
  const std::vector<double> x = {3, 3, 1, 1, 3, 3, 1, 1};
  const MeanError e = mean_error(x);
  EXPECT_DOUBLE_EQ(e.mean, 2);
  EXPECT_DOUBLE_EQ(e.error, std::sqrt(1.0 / 7));  // sample variance 8/7 over 8 samples
  EXPECT_EQ(e.dof, 7);
  EXPECT_FALSE(e.plateau);
  EXPECT_EQ(mean_error(std::vector<double>(8, 2.0)).error, 0);  // a constant series: exactly 0
}

namespace {

// Contact angles formed at the intruder, per sample interval: events (new grains) arrive as a
// Poisson process of `rate` per interval, each at an angle ~ N(1.2, 0.4), and form their contact
// again once in each of the next `repeats` - 1 intervals (a grain chattering on and off), so
// the angles of one grain are counted `repeats` times.
struct AngleSeries {
  std::vector<double> sums, counts;
};
AngleSeries chattering_angles(long intervals, double rate, int repeats, std::mt19937_64& rng) {
  std::poisson_distribution<int> arrivals(rate);
  std::normal_distribution<double> angle(1.2, 0.4);
  AngleSeries a{std::vector<double>(intervals + repeats, 0.0), std::vector<double>(intervals + repeats, 0.0)};
  for (long k = 0; k < intervals; ++k)
    for (int e = arrivals(rng); e > 0; --e) {
      const double theta = angle(rng);
      for (int r = 0; r < repeats; ++r) a.sums[k + r] += theta, a.counts[k + r] += 1;
    }
  a.sums.resize(intervals);
  a.counts.resize(intervals);
  return a;
}

// The spread of the ratio over independent realizations, and the mean of ratio_error's estimate
// and of the independent-items error sd / sqrt(count) (what theta's error was before).
struct RatioCheck {
  double spread = 0, estimated = 0, independent_items = 0;
};
RatioCheck check_ratio(int repeats) {
  std::mt19937_64 rng(11 + repeats);
  const int realizations = 400;
  double sum = 0, sq = 0;
  RatioCheck c;
  for (int r = 0; r < realizations; ++r) {
    const AngleSeries a = chattering_angles(2000, 0.5, repeats, rng);
    const MeanError e = ratio_error(a.sums, a.counts);
    sum += e.mean, sq += e.mean * e.mean;
    c.estimated += e.error / realizations;
    double n = 0;
    for (double x : a.counts) n += x;
    c.independent_items += 0.4 / std::sqrt(n) / realizations;
  }
  const double m = sum / realizations;
  c.spread = std::sqrt((sq / realizations - m * m) * realizations / (realizations - 1));
  std::printf("angles counted %d times: spread of the ratio %.5f, ratio_error %.5f, sd/sqrt(count) %.5f\n",
              repeats, c.spread, c.estimated, c.independent_items);
  return c;
}

}  // namespace

TEST(Observables, TheRatioErrorOfIndependentAnglesIsTheirStandardError) {
  // 1,000 angles per realization, sd 0.4: 0.0126. The spread of 400 realizations is known to
  // 3.5 %; the estimate is held to 12 % of it.
  const RatioCheck c = check_ratio(1);
  EXPECT_NEAR(c.spread, 0.4 / std::sqrt(1000.0), 0.1 * c.spread);
  EXPECT_NEAR(c.estimated, c.spread, 0.12 * c.spread);
  EXPECT_NEAR(c.independent_items, c.spread, 0.12 * c.spread);
}

TEST(Observables, TheRatioErrorCountsAChatteringGrainOnceNotEachTimeItTouches) {
  // Each grain's angle counted 6 times over 6 intervals: 6,000 angles but 1,000 independent
  // ones. The items' sd / sqrt(count) is sqrt(6) = 2.45 times too small; ratio_error is not.
  const RatioCheck c = check_ratio(6);
  EXPECT_NEAR(c.spread, 0.4 / std::sqrt(1000.0), 0.1 * c.spread);
  EXPECT_NEAR(c.estimated, c.spread, 0.15 * c.spread);
  EXPECT_LT(c.independent_items, 0.5 * c.spread);
}

TEST(Observables, TheRatioErrorNeedsEightIntervalsAndAnItem) {
  EXPECT_TRUE(std::isnan(ratio_error(std::vector<double>(8, 0.0), std::vector<double>(8, 0.0)).mean));
  const MeanError few = ratio_error({1, 2, 3}, {1, 1, 1});
  EXPECT_DOUBLE_EQ(few.mean, 2);
  EXPECT_TRUE(std::isnan(few.error));
}

TEST(Observables, PrefixErrorsAreTheErrorsOfGrowingPrefixes) {
  std::mt19937_64 rng(3);
  const std::vector<double> x = ar1(300, std::exp(-0.2), rng);
  const std::vector<PrefixError> p = prefix_errors(x);
  // 8, 11, 16, 23, 32, 45, 64, 91, 128, 181, 256, then all 300.
  ASSERT_EQ(p.size(), 12u);
  EXPECT_EQ(p.front().samples, 8);
  EXPECT_EQ(p[1].samples, 11);
  EXPECT_EQ(p.back().samples, 300);
  for (std::size_t k = 0; k < p.size(); ++k) {
    if (k > 0) {
      EXPECT_GT(p[k].samples, p[k - 1].samples);
    }
    const MeanError direct = mean_error(std::vector<double>(x.begin(), x.begin() + p[k].samples));
    EXPECT_EQ(p[k].estimate.mean, direct.mean);
    EXPECT_EQ(p[k].estimate.error, direct.error);
    EXPECT_EQ(p[k].estimate.dof, direct.dof);
  }
  EXPECT_TRUE(prefix_errors(std::vector<double>(7, 1.0)).empty());
  EXPECT_EQ(prefix_errors(std::vector<double>(8, 1.0)).size(), 1u);
}

TEST(Observables, CumulativeAverage) {
  const std::vector<double> c = cumulative_average({2, 4, 6});
  EXPECT_DOUBLE_EQ(c[0], 2);
  EXPECT_DOUBLE_EQ(c[1], 3);
  EXPECT_DOUBLE_EQ(c[2], 4);
}

TEST(CoordinationShells, RingsAreHalfOpenAndNested) {
  EXPECT_EQ(CoordinationShells::ring(-0.3), 0);  // overlapping the intruder: the first ring
  EXPECT_EQ(CoordinationShells::ring(0.4999), 0);
  EXPECT_EQ(CoordinationShells::ring(0.5), 1);
  EXPECT_EQ(CoordinationShells::ring(5.99), 8);
  EXPECT_EQ(CoordinationShells::ring(6.0), -1);
  CoordinationShells s;
  s.grains = {2, 0, 2, 0, 0, 0, 0, 0, 0};
  s.contacts = {8, 0, 4, 0, 0, 0, 0, 0, 0};
  const std::vector<double> z = s.z();
  EXPECT_DOUBLE_EQ(z[0], 4.0);
  EXPECT_DOUBLE_EQ(z[1], 4.0);  // an empty ring changes nothing
  EXPECT_DOUBLE_EQ(z[2], 3.0);  // (8 + 4) contacts of 4 grains
  EXPECT_DOUBLE_EQ(z[8], 3.0);
}
