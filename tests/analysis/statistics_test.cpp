// Tests for src/analysis/statistics.cpp
#include "unjam/analysis/statistics.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>
#include <vector>

namespace unjam {
namespace {

TEST(StatisticsMean, KnownSamples) {
  // Mean 5, sample variance Σ(x − 5)² / 7 = 32 / 7.
  const MeanAndError m = MeanWithError({2, 4, 4, 4, 5, 5, 7, 9});
  EXPECT_EQ(m.count, 8);
  EXPECT_DOUBLE_EQ(m.mean, 5.0);
  EXPECT_NEAR(m.error, std::sqrt(32.0 / 7.0 / 8.0), 1e-15);
}

TEST(StatisticsMean, FewerThanTwoSamplesHaveNoError) {
  const MeanAndError one = MeanWithError({3.5});
  EXPECT_EQ(one.count, 1);
  EXPECT_EQ(one.mean, 3.5);
  EXPECT_EQ(one.error, 0.0);
  const MeanAndError none = MeanWithError({});
  EXPECT_EQ(none.count, 0);
  EXPECT_EQ(none.error, 0.0);
}

TEST(StatisticsMean, LargeOffsetDoesNotCancel) {
  // Naive Σx² − n·mean² loses every digit here.
  const MeanAndError m = MeanWithError({1e9 + 1, 1e9 + 2, 1e9 + 3});
  EXPECT_DOUBLE_EQ(m.mean, 1e9 + 2);
  EXPECT_NEAR(m.error, std::sqrt(1.0 / 3.0), 1e-9);
}

TEST(StatisticsPearson, LinearDataIsPerfectlyCorrelated) {
  std::vector<double> x, y, z;
  for (int k = 0; k < 10; ++k) {
    x.push_back(0.3 * k - 1.0);
    y.push_back(2.0 * x.back() + 1.0);
    z.push_back(-0.5 * x.back() + 7.0);
  }
  EXPECT_NEAR(PearsonCorrelation(x, y), 1.0, 1e-14);
  EXPECT_NEAR(PearsonCorrelation(x, z), -1.0, 1e-14);
}

TEST(StatisticsPearson, KnownValue) {
  // x = (1,2,3), y = (1,3,2): covariance 0.5·2, variances 2 and 2 → r = 0.5.
  EXPECT_NEAR(PearsonCorrelation({1, 2, 3}, {1, 3, 2}), 0.5, 1e-15);
}

TEST(StatisticsPearson, DegenerateCasesAreZeroAndSizeMismatchThrows) {
  EXPECT_EQ(PearsonCorrelation({1, 2, 3}, {4, 4, 4}), 0.0);
  EXPECT_EQ(PearsonCorrelation({1}, {2}), 0.0);
  EXPECT_EQ(PearsonCorrelation({}, {}), 0.0);
  EXPECT_THROW(PearsonCorrelation({1, 2, 3}, {1, 2}), std::invalid_argument);
}

TEST(StatisticsLogBinned, LayoutCountsAndMeans) {
  // Two bins per decade over [1, 100): edges 1, √10, 10, 10√10, 100.
  const std::vector<double> r = {1.0, 2.0, 3.0, 5.0, 10.0, 50.0, 0.5, 100.0, 200.0, -1.0, 0.0};
  const std::vector<double> v = {1.0, 3.0, 5.0, 7.0, 9.0, 11.0, 99.0, 99.0, 99.0, 99.0, 99.0};
  const std::vector<LogBin> bins = LogBinned(r, v, 1.0, 100.0, 2);
  ASSERT_EQ(bins.size(), 4u);
  const double s10 = std::sqrt(10.0);
  const double expected_edges[] = {1.0, s10, 10.0, 10.0 * s10, 100.0};
  for (int k = 0; k < 4; ++k) {
    EXPECT_NEAR(bins[k].r_low, expected_edges[k], 1e-12 * expected_edges[k]) << k;
    EXPECT_NEAR(bins[k].r_high, expected_edges[k + 1], 1e-12 * expected_edges[k + 1]) << k;
  }
  // Bin 0: r = 1, 2, 3 (3 < √10); bin 1: r = 5; bin 2: r = 10; bin 3: r = 50.
  EXPECT_EQ(bins[0].count, 3);
  EXPECT_EQ(bins[1].count, 1);
  EXPECT_EQ(bins[2].count, 1);
  EXPECT_EQ(bins[3].count, 1);
  EXPECT_DOUBLE_EQ(bins[0].mean, 3.0);
  EXPECT_DOUBLE_EQ(bins[0].r_mean, 2.0);
  EXPECT_NEAR(bins[0].error, 2.0 / std::sqrt(3.0), 1e-15);  // sample sd 2
  EXPECT_EQ(bins[1].mean, 7.0);
  EXPECT_EQ(bins[2].mean, 9.0);  // 10 is the lower edge of bin 2, not the top of bin 1
  EXPECT_EQ(bins[3].mean, 11.0);
  EXPECT_EQ(bins[3].r_mean, 50.0);
}

TEST(StatisticsLogBinned, EmptyBinsAreKept) {
  const std::vector<LogBin> bins = LogBinned({1.5, 150.0}, {1.0, 2.0}, 1.0, 1000.0, 1);
  ASSERT_EQ(bins.size(), 3u);
  EXPECT_EQ(bins[0].count, 1);
  EXPECT_EQ(bins[1].count, 0);
  EXPECT_EQ(bins[1].mean, 0.0);
  EXPECT_EQ(bins[2].count, 1);
  EXPECT_DOUBLE_EQ(bins[1].r_low, 10.0);
  EXPECT_DOUBLE_EQ(bins[1].r_high, 100.0);
}

TEST(StatisticsLogBinned, BadArgumentsThrow) {
  EXPECT_THROW(LogBinned({1.0}, {1.0, 2.0}, 1.0, 10.0, 2), std::invalid_argument);
  EXPECT_THROW(LogBinned({1.0}, {1.0}, 0.0, 10.0, 2), std::invalid_argument);
  EXPECT_THROW(LogBinned({1.0}, {1.0}, 10.0, 1.0, 2), std::invalid_argument);
  EXPECT_THROW(LogBinned({1.0}, {1.0}, 1.0, 10.0, 0), std::invalid_argument);
}

TEST(StatisticsPowerLaw, RecoversExactExponent) {
  std::vector<double> r, v;
  for (int k = 0; k < 40; ++k) {
    r.push_back(1.1 * std::pow(10.0, k / 10.0));  // one sample per bin: bin mean exact
    v.push_back(3.0 * std::pow(r.back(), -1.5));
  }
  const std::vector<LogBin> bins = LogBinned(r, v, 1.0, 1e4, 10);
  const PowerLawFit fit = FitPowerLaw(bins, 0.0, 1e9);
  EXPECT_EQ(fit.points, 40);
  EXPECT_NEAR(fit.alpha, 1.5, 1e-12);
  EXPECT_NEAR(fit.prefactor, 3.0, 1e-10);
  EXPECT_NEAR(fit.alpha_error, 0.0, 1e-10);
}

TEST(StatisticsPowerLaw, FitRangeSelectsBins) {
  // Slope 1 below r = 10, slope 2 above: the fit range must pick the second.
  std::vector<LogBin> bins;
  for (int k = 0; k < 20; ++k) {
    LogBin b;
    b.r_mean = std::pow(10.0, k / 5.0);
    b.mean = b.r_mean < 10.0 ? 1.0 / b.r_mean : 10.0 / (b.r_mean * b.r_mean);
    b.count = 1;
    bins.push_back(b);
  }
  const PowerLawFit fit = FitPowerLaw(bins, 10.0, 1e4);
  EXPECT_EQ(fit.points, 15);  // r = 10^(k/5), k = 5 … 19
  EXPECT_NEAR(fit.alpha, 2.0, 1e-12);
  EXPECT_NEAR(fit.prefactor, 10.0, 1e-10);
  EXPECT_EQ(fit.fit_min, 10.0);
  EXPECT_EQ(fit.fit_max, 1e4);
}

TEST(StatisticsPowerLaw, NoisyDataGivesAPlausibleError) {
  std::mt19937_64 rng(20240611);
  std::normal_distribution<double> noise(0.0, 0.1);
  std::uniform_real_distribution<double> log_r(0.0, 3.0);
  std::vector<double> r, v;
  for (int s = 0; s < 20000; ++s) {
    r.push_back(std::pow(10.0, log_r(rng)));
    v.push_back(3.0 * std::pow(r.back(), -1.5) * std::exp(noise(rng)));
  }
  const std::vector<LogBin> bins = LogBinned(r, v, 1.0, 1000.0, 5);
  const PowerLawFit fit = FitPowerLaw(bins, 1.0, 1000.0);
  EXPECT_EQ(fit.points, 15);
  // About 1300 samples per bin with 10 % noise: an error of a few 1e-4.
  EXPECT_GT(fit.alpha_error, 1e-4);
  EXPECT_LT(fit.alpha_error, 1e-2);
  // Uniform in log r, every log bin averages r^-1.5 and the noise alike (scale invariance):
  // bin means are biased by one common factor, and the slope is unbiased.
  EXPECT_NEAR(fit.alpha, 1.5, 4.0 * fit.alpha_error);
  EXPECT_GT(fit.prefactor, 3.0);  // the common bias is upward (convex r^-1.5, lognormal noise)
}

TEST(StatisticsPowerLaw, FewerThanThreePointsIsNoFit) {
  const std::vector<LogBin> bins = LogBinned({2.0, 20.0, 200.0}, {1.0, 0.1, 0.01}, 1.0, 1000.0, 1);
  const PowerLawFit fit = FitPowerLaw(bins, 1.0, 100.0);  // r_mean 200 is outside
  EXPECT_EQ(fit.points, 2);
  EXPECT_TRUE(std::isnan(fit.alpha));
  const PowerLawFit all = FitPowerLaw(bins, 1.0, 1000.0);
  EXPECT_EQ(all.points, 3);
  EXPECT_NEAR(all.alpha, 1.0, 1e-12);
}

TEST(StatisticsPowerLaw, NonPositiveMeansAreSkipped) {
  std::vector<LogBin> bins(4);
  const double rs[] = {1.0, 2.0, 4.0, 8.0};
  const double means[] = {1.0, -5.0, 1.0 / 16.0, 1.0 / 64.0};
  for (int k = 0; k < 4; ++k) {
    bins[k].r_mean = rs[k];
    bins[k].mean = means[k];
    bins[k].count = 1;
  }
  const PowerLawFit fit = FitPowerLaw(bins, 0.0, 100.0);
  EXPECT_EQ(fit.points, 3);
  EXPECT_NEAR(fit.alpha, 2.0, 1e-12);
}

TEST(StatisticsExponentialTail, RecoversTheScale) {
  std::mt19937_64 rng(7);
  std::exponential_distribution<double> exponential(1.0 / 2.5);  // scale 2.5
  std::vector<double> samples(20000);
  for (double& s : samples) s = 0.3 + exponential(rng);
  const ExponentialTailFit fit = FitExponentialTail(samples, 1.0);
  EXPECT_GT(fit.count, 15000);
  EXPECT_LT(fit.count, 20000);
  EXPECT_NEAR(fit.scale_error, fit.scale / std::sqrt(fit.count), 1e-15);
  // Memoryless: above any threshold the excess has the same scale.
  EXPECT_NEAR(fit.scale, 2.5, 3.0 * fit.scale_error);
  EXPECT_EQ(fit.threshold, 1.0);
}

TEST(StatisticsExponentialTail, KnownSamplesAndEmptyTail) {
  const ExponentialTailFit fit = FitExponentialTail({0.5, 1.0, 2.0, 4.0}, 1.0);
  EXPECT_EQ(fit.count, 2);           // strictly above the threshold
  EXPECT_DOUBLE_EQ(fit.scale, 2.0);  // mean of 1 and 3
  const ExponentialTailFit none = FitExponentialTail({0.5, 1.0}, 1.0);
  EXPECT_EQ(none.count, 0);
  EXPECT_TRUE(std::isnan(none.scale));
}

TEST(StatisticsHistogram, DensitiesIntegrateToTheFractionInside) {
  std::mt19937_64 rng(3);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::vector<double> samples(5000);
  for (double& s : samples) s = normal(rng);
  const Histogram h = MakeHistogram(samples, -1.5, 2.0, 14);
  ASSERT_EQ(h.density.size(), 14u);
  int inside = 0;
  double integral = 0.0;
  for (int k = 0; k < 14; ++k) {
    inside += h.counts[k];
    integral += h.density[k] * 0.25;
  }
  EXPECT_GT(h.outside, 0);
  EXPECT_EQ(inside + h.outside, 5000);
  EXPECT_NEAR(integral, (5000.0 - h.outside) / 5000.0, 1e-12);
}

TEST(StatisticsHistogram, KnownCountsAndEdges) {
  const Histogram h = MakeHistogram({0.0, 0.1, 0.5, 0.99, 1.0, -0.1}, 0.0, 1.0, 2);
  EXPECT_EQ(h.counts, (std::vector<int>{2, 2}));  // [0, 0.5) and [0.5, 1)
  EXPECT_EQ(h.outside, 2);                        // 1.0 and −0.1
  EXPECT_DOUBLE_EQ(h.density[0], 2.0 / (6.0 * 0.5));
  EXPECT_THROW(MakeHistogram({1.0}, 1.0, 1.0, 3), std::invalid_argument);
  EXPECT_THROW(MakeHistogram({1.0}, 0.0, 1.0, 0), std::invalid_argument);
}

}  // namespace
}  // namespace unjam
