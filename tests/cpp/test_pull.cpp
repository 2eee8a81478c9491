// Pulls on a small bed: the statistics, the observables' definitions, and checkpoint/resume
// bitwise identical to an uninterrupted run.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <string>

#include "core/error.hpp"
#include "helpers.hpp"
#include "io/h5_file.hpp"
#include "protocol/observables.hpp"
#include "protocol/pull.hpp"

using namespace granudrag;

namespace {

using support::small_bed;

}  // namespace

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

TEST(Observables, NinetyFivePercentIntervalsCoverRealForceSeries) {
  // 48 recorded drag series (tests/data/make_drag_series.sh: one pull each, each through its own
  // bed, about 9,900 samples; their autocorrelation crosses 0 near 28 samples and has a negative
  // lobe near 50, the shape mean_error's step (5) is for). Every disjoint window of n samples is
  // a repeat; windows of different pulls are independent, and disjoint windows of one pull are
  // nearly so (the correlation time, ~5 samples, is short beside n), so the coverage below rests
  // on 464 (n = 1,024) to 7,440 (n = 64) repeats: its binomial standard error is 0.010 to 0.003.
  // The truth of a window is its pull's mean (the beds differ: their drags scatter by ~5 %).
  // A window is part of that mean, so mean_w - mean_pull has the variance Var(mean_w)(1 - n/N)
  // for n much longer than the correlation time; the deviation is divided by sqrt(1 - n/N) to
  // put it back on the window mean's own scale (without it, 1,024 samples would cover ~1 %
  // too often).
  const std::string path =
      std::string(__FILE__).substr(0, std::string(__FILE__).rfind('/')) + "/../data/drag_series_D2_V1.h5";
  const h5::File file = h5::File::open(path);
  const std::vector<double> all = file.read_doubles("/drag");
  const long length = file.get_attr_int64("/drag", "series_length");
  ASSERT_GT(length, 9000);
  ASSERT_EQ(all.size() % length, 0u);
  const long series = static_cast<long>(all.size()) / length;
  ASSERT_GE(series, 40);
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
    // The band of the synthetic tests, widened by twice the sampling error a coverage on the
    // band's edge would have over these repeats (binomial): a coverage beyond that is off the
    // band, not unlucky. At 64 samples 0.893-0.983, at 1,024 0.871-0.993.
    const double k = static_cast<double>(repeats);
    const double low = 0.90 - 2 * std::sqrt(0.90 * 0.10 / k), high = 0.98 + 2 * std::sqrt(0.98 * 0.02 / k);
    std::printf("recorded drag series, %ld samples: coverage %.3f of %ld repeats (band %.3f-%.3f)\n", n, c,
                repeats, low, high);
    // Measured 0.909, 0.979, 0.955, 0.986 (with the N/7 fallback window: 0.890 at 64 samples).
    EXPECT_GE(repeats, 400) << n << " samples";
    EXPECT_GE(c, low) << n << " samples";
    EXPECT_LE(c, high) << n << " samples";
  }
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

TEST(Pull, FroudeNumberIsPaperEq4) { EXPECT_DOUBLE_EQ(froude_number(1.0, 4.0), 2.0 * std::sqrt(8.0) / 5.0); }

TEST(Pull, MeasuresDragAndContactsOfAMovingIntruder) {
  PullSpec spec;
  spec.speed = 1.0;
  spec.distance = 3.0;
  Pull pull(small_bed(), spec);
  pull.run(false);
  const PullResult r = pull.result();
  EXPECT_GT(r.drag, 0.0);  // resists the motion along +x
  EXPECT_NEAR(r.drag, -mean({pull.record().fx.begin() + r.transient_samples, pull.record().fx.end()}),
              1e-12 * r.drag);
  EXPECT_GT(r.drag_error, 0.0);
  EXPECT_LT(r.drag_error, r.drag);
  EXPECT_GT(r.coordination, 3.0);
  EXPECT_GT(r.coordination_error, 0.0);  // the intruder's contacts fluctuate
  EXPECT_LT(r.coordination_error, 0.5 * r.coordination);
  EXPECT_GT(r.theta, 0.0);
  EXPECT_LT(r.theta, M_PI / 2);  // contacts form in front of the intruder
  EXPECT_GT(r.bulk_coordination, 2.0);
  EXPECT_LT(r.bulk_coordination, 8.0);
  double total = 0;
  for (double pz : r.z_distribution) total += pz;
  EXPECT_NEAR(total, 1.0, 1e-12);
  EXPECT_NEAR(r.kappa, r.bulk_coordination / r.coordination * 9.0 / (2 * std::sqrt(3.0)), 1e-12);
  // The nested shells count the same samples: at the main shell's width (2 d) their Z is the
  // histogram's, accumulated separately; kappa follows Eq. 8 in each.
  ASSERT_EQ(r.shell_z.size(), CoordinationShells::widths.size());
  EXPECT_EQ(CoordinationShells::widths[3], spec.shell);
  EXPECT_NEAR(r.shell_z[3], r.bulk_coordination, 1e-12);
  for (std::size_t k = 0; k < r.shell_z.size(); ++k)
    EXPECT_NEAR(r.shell_kappa[k], r.shell_z[k] / r.coordination * 9.0 / (2 * std::sqrt(3.0)), 1e-12);
  EXPECT_GT(pull.record().shells.grains[0], 0);  // touching grains were seen
  EXPECT_EQ(pull.record().snapshots.size(), 3u);
  // The intruder moved exactly the requested distance (rounded up to whole samples).
  const Particles& p = pull.simulation().particles();
  const double travelled = pull.simulation().time() * spec.speed;
  EXPECT_GE(travelled, 3.0 - 1e-9);
  EXPECT_DOUBLE_EQ(p.x[small_bed().intruder].z(), small_bed().state.particles.x[small_bed().intruder].z());
  // Work done on the grains is the drag times the distance, up to the transient.
  EXPECT_NEAR(pull.record().work / travelled, -mean(pull.record().fx), 1e-9 * pull.record().work);
}

TEST(Pull, ResumedFromCheckpointIsBitwiseIdentical) {
  PullSpec spec;
  spec.speed = 0.5;
  spec.distance = 1.0;
  spec.checkpoint_every = 500;
  Pull whole(small_bed(), spec);
  std::vector<std::pair<Simulation::State, PullRecord>> checkpoints;
  whole.run(false, [&](const Pull& p) { checkpoints.emplace_back(p.state(), p.record()); });
  ASSERT_GE(checkpoints.size(), 2u);
  // "Kill" after the first checkpoint and resume from it.
  Pull resumed(small_bed(), spec, checkpoints[0].first, checkpoints[0].second);
  resumed.run(false, [](const Pull&) {});
  const Particles& a = whole.simulation().particles();
  const Particles& b = resumed.simulation().particles();
  for (std::size_t i = 0; i < a.size(); ++i) {
    ASSERT_EQ(a.x[i], b.x[i]) << i;
    ASSERT_EQ(a.v[i], b.v[i]) << i;
    ASSERT_EQ(a.omega[i], b.omega[i]) << i;
  }
  EXPECT_EQ(whole.result().drag, resumed.result().drag);
  EXPECT_EQ(whole.record().fx, resumed.record().fx);
}

TEST(Pull, FramesComeAtStepZeroAndEveryDumpIntervalAndResumeWhereTheCheckpointCounted) {
  PullSpec spec;
  spec.speed = 0.5;
  spec.distance = 1.0;
  spec.checkpoint_every = 500;
  spec.dump_every = 300;
  Pull whole(small_bed(), spec);
  std::vector<long> steps;
  std::vector<std::vector<Vec3>> positions;
  std::vector<std::pair<Simulation::State, PullRecord>> checkpoints;
  whole.run(
      false, [&](const Pull& p) { checkpoints.emplace_back(p.state(), p.record()); },
      [&](const Pull& p) {
        steps.push_back(p.simulation().steps_done());
        positions.push_back(p.simulation().particles().x);
      });
  const long total = whole.record().total_steps;
  ASSERT_EQ(whole.record().frames, total / 300 + 1);
  for (std::size_t k = 0; k < steps.size(); ++k) EXPECT_EQ(steps[k], static_cast<long>(300 * k));
  EXPECT_EQ(positions.front(), small_bed().state.particles.x);  // frame 0 is the bed as poured
  EXPECT_EQ(positions.back() == whole.simulation().particles().x, total % 300 == 0);
  // Resumed from the first checkpoint (step 500: frames 0 and 300 counted), the frames go on
  // from step 600, the same bit for bit.
  ASSERT_GE(checkpoints.size(), 1u);
  EXPECT_EQ(checkpoints[0].second.frames, 2);
  Pull resumed(small_bed(), spec, checkpoints[0].first, checkpoints[0].second);
  std::vector<long> resumed_steps;
  std::vector<std::vector<Vec3>> resumed_positions;
  // Checkpoints force list rebuilds, which a resumed run must do at the same steps.
  resumed.run(
      false, [](const Pull&) {},
      [&](const Pull& p) {
        resumed_steps.push_back(p.simulation().steps_done());
        resumed_positions.push_back(p.simulation().particles().x);
      });
  EXPECT_EQ(resumed.record().frames, whole.record().frames);
  ASSERT_EQ(resumed_steps, std::vector<long>(steps.begin() + 2, steps.end()));
  for (std::size_t k = 0; k < resumed_positions.size(); ++k)
    EXPECT_EQ(resumed_positions[k], positions[k + 2]) << k;
}

TEST(Pull, ATargetErrorStopsThePullOnceTheDragIsThatPrecise) {
  PullSpec spec;
  // On this small periodic bed the drag decorrelates over 2-4 d of travel: 10 effective
  // samples, the rule's least, take 25-45 d, depending on the thread count (which changes the
  // trajectory's rounding, so its details).
  spec.speed = 3.0;
  spec.max_overlap = 0.2;  // soft grains at V = 3, as the default study sets
  spec.distance = 90.0;
  spec.target_error = 0.1;
  spec.min_distance = 2.0;
  Pull pull(small_bed(), spec);
  pull.run(false);
  const PullResult r = pull.result();
  const double travelled = pull.simulation().time() * spec.speed;
  EXPECT_EQ(pull.record().stop_reason, "target_error");
  EXPECT_LT(travelled, 90.0 - 10);  // stopped well before the distance
  EXPECT_GE(travelled, 2.0);        // not before min_distance
  EXPECT_EQ(pull.record().total_steps, pull.simulation().steps_done());
  // The result is computed over the samples the stopping rule saw: its error meets the target.
  EXPECT_LE(r.drag_error, 0.1 * r.drag);
  EXPECT_GE(r.drag_dof, 10);
  // Unmet, the same pull travels the whole distance and says so.
  spec.target_error = 1e-4;
  Pull whole(small_bed(), spec);
  whole.run(false);
  EXPECT_EQ(whole.record().stop_reason, "distance");
  EXPECT_GE(whole.simulation().time() * spec.speed, 90.0 - 1e-9);
  EXPECT_GT(whole.result().drag_error, 1e-4 * whole.result().drag);
  // The stopped pull is the first part of the whole one, sample for sample.
  const std::vector<double>& a = pull.record().fx;
  EXPECT_TRUE(std::equal(a.begin(), a.end(), whole.record().fx.begin()));
}

TEST(Pull, AResumedPullStopsAtTheSameStepAsAnUninterruptedOne) {
  PullSpec spec;
  spec.speed = 3.0;
  spec.max_overlap = 0.2;  // soft grains at V = 3, as the default study sets
  spec.distance = 90.0;
  spec.target_error = 0.1;
  spec.min_distance = 2.0;
  spec.checkpoint_every = 4000;
  Pull whole(small_bed(), spec);
  std::vector<std::pair<Simulation::State, PullRecord>> checkpoints;
  whole.run(false, [&](const Pull& p) { checkpoints.emplace_back(p.state(), p.record()); });
  ASSERT_EQ(whole.record().stop_reason, "target_error");
  ASSERT_GE(checkpoints.size(), 2u);
  Pull resumed(small_bed(), spec, checkpoints[1].first, checkpoints[1].second);
  resumed.run(false, [](const Pull&) {});
  EXPECT_EQ(resumed.record().stop_reason, "target_error");
  EXPECT_EQ(resumed.simulation().steps_done(), whole.simulation().steps_done());
  EXPECT_EQ(resumed.record().fx, whole.record().fx);
  EXPECT_EQ(resumed.result().drag, whole.result().drag);
}

TEST(Pull, StoppingChecksAreSparseAndFallOnFixedSampleCounts) {
  long checks = 0;
  for (long n = 1; n <= 100000; ++n) checks += stopping_check_due(n);
  EXPECT_FALSE(stopping_check_due(15));
  EXPECT_TRUE(stopping_check_due(16));
  EXPECT_GT(checks, 16 * 12);  // 16 per doubling from 16 to 1e5 (12.6 doublings)
  EXPECT_LT(checks, 16 * 14);
  EXPECT_TRUE(stopping_check_due(1024) && stopping_check_due(1088) && !stopping_check_due(1089));
}

TEST(Pull, ABlowUpStopsTheRunWithAMessage) {
  Bed broken = small_bed();
  broken.state.particles.v[0] = Vec3(NAN, 0, 0);  // a NaN that will spread through contacts
  PullSpec spec;
  spec.distance = 1.0;
  int checkpoints = 0;
  Pull pull(broken, spec);
  try {
    pull.run(false, [&](const Pull&) { ++checkpoints; });
    FAIL() << "a NaN velocity ran to the end";
  } catch (const Error& e) {
    const std::string msg = e.what();
    EXPECT_TRUE(msg.find("blew up") != std::string::npos || msg.find("non-finite") != std::string::npos)
        << msg;
  }
  EXPECT_EQ(checkpoints, 0);  // nothing bad was checkpointed
}

TEST(Pull, RejectsBadInput) {
  PullSpec spec;
  spec.speed = -1;
  EXPECT_THROW(Pull(small_bed(), spec), Error);
  spec = PullSpec{};
  spec.target_error = 2;  // a relative error above 1
  EXPECT_THROW(Pull(small_bed(), spec), Error);
  spec.target_error = 0.05;
  spec.distance = 3;
  spec.min_distance = 3;  // the target could never stop it
  try {
    Pull(small_bed(), spec);
    FAIL() << "min_distance = distance accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("min_distance"), std::string::npos) << e.what();
  }
  Bed no_intruder = small_bed();
  no_intruder.intruder = -1;
  EXPECT_THROW(Pull(no_intruder, PullSpec{}), Error);
}

TEST(Pull, ABedWhoseGrainsOverlapBeyondTheGuardIsRefusedWithThatReason) {
  Bed bed = small_bed();
  Particles& p = bed.state.particles;
  std::size_t a = 0;
  while (p.species[a] != Species::Mobile) ++a;
  std::size_t b = a + 1;  // the nearest other grain, moved onto a to overlap it by 0.3 d
  for (std::size_t k = 0; k < p.size(); ++k)
    if (k != a && p.species[k] == Species::Mobile &&
        bed.box.min_image(p.x[k] - p.x[a]).norm() < bed.box.min_image(p.x[b] - p.x[a]).norm())
      b = k;
  const Vec3 along = bed.box.min_image(p.x[b] - p.x[a]).normalized();
  p.x[b] = p.x[a] + along * (p.radius[a] + p.radius[b] - 0.3);
  try {
    Pull pull(bed, PullSpec{});
    FAIL() << "accepted";
  } catch (const Error& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("overlapping by 0.3"), std::string::npos) << m;
    EXPECT_NE(m.find("damaged"), std::string::npos) << m;
  }
  EXPECT_NO_THROW(Pull(small_bed(), PullSpec{}));
}

TEST(Pull, ASpeedTheBedCannotResolveIsRefusedBeforeAnyStep) {
  PullSpec spec;
  spec.speed = 1e6;  // ran to the end with NaN before the speed limits
  try {
    Pull pull(small_bed(), spec);
    FAIL() << "V = 1e6 was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("the largest speed that works is"), std::string::npos) << e.what();
  }
}

TEST(Pull, AnOverlapOverTheBoundStopsTheRunOrIsRecordedWithKeepGoing) {
  // V = 6 passes the impact estimate at kn = 2e4 (largest speed 6.6) but the bed, loaded from
  // behind, overlaps the grain ahead of the intruder by 0.113 d: the guard stops it.
  PullSpec spec;
  spec.speed = 6;
  spec.distance = 1.0;
  int checkpoints = 0;
  {
    Pull pull(small_bed(), spec);
    try {
      pull.run(false, [&](const Pull&) { ++checkpoints; });
      FAIL() << "an overlap over 0.1 d ran to the end";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("exceeds max_overlap = 0.1 d"), std::string::npos) << e.what();
    }
  }
  spec.keep_going = true;
  Pull pull(small_bed(), spec);
  pull.run(false);
  EXPECT_TRUE(pull.finished());
  EXPECT_NE(pull.verdict().find("exceeds max_overlap"), std::string::npos) << pull.verdict();
  EXPECT_GT(pull.record().max_overlap, 0.1);
  // A larger bound passes the same pull clean.
  spec.keep_going = false;
  spec.max_overlap = 0.2;
  Pull clean(small_bed(), spec);
  clean.run(false);
  EXPECT_EQ(clean.verdict(), "clean");
}
