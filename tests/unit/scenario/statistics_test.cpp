// Binomial statistics against their closed forms and defining properties (paper §V-B).

#include "emrm/scenario/statistics.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

namespace emrm::scenario {
namespace statistics_test {

// Wilson half-width written out from the score-interval formula, independently of the library.
double wilson_half_width_by_formula(double k, double n, double z) {
  const double p = k / n;
  return z / (1.0 + z * z / n) * std::sqrt(p * (1.0 - p) / n + z * z / (4.0 * n * n));
}

TEST(StatisticsNormalQuantile, MatchesTabulatedValues) {
  EXPECT_NEAR(normal_quantile(0.95), 1.959964, 1e-6);
  EXPECT_NEAR(normal_quantile(0.90), 1.644854, 1e-6);
  EXPECT_NEAR(normal_quantile(0.99), 2.575829, 1e-6);
  EXPECT_NEAR(normal_quantile(0.6826894921370859), 1.0, 1e-9);
}

TEST(StatisticsNormalQuantile, RejectsConfidenceOutsideTheOpenUnitInterval) {
  EXPECT_THROW((void)normal_quantile(0.0), std::invalid_argument);
  EXPECT_THROW((void)normal_quantile(1.0), std::invalid_argument);
  EXPECT_THROW((void)normal_quantile(-0.5), std::invalid_argument);
  EXPECT_THROW((void)normal_quantile(std::nan("")), std::invalid_argument);
}

TEST(WilsonInterval, EightOfTenAtNinetyFivePercentIsTheTextbookInterval) {
  const Interval i = wilson_interval(8, 10, 0.95);
  EXPECT_NEAR(i.low, 0.490, 5e-4);
  EXPECT_NEAR(i.high, 0.943, 5e-4);
}

TEST(WilsonInterval, MatchesTheScoreFormulaCentreAndHalfWidth) {
  const double z = normal_quantile(0.9);
  for (const double n : {1.0, 7.0, 20.0, 133.0}) {
    for (double k = 1; k < n; k += 3) {
      const Interval i = wilson_interval(k, n, 0.9);
      const double centre = (k / n + z * z / (2 * n)) / (1 + z * z / n);
      EXPECT_NEAR(0.5 * (i.low + i.high), centre, 1e-12);
      EXPECT_NEAR(i.half_width(), wilson_half_width_by_formula(k, n, z), 1e-12);
    }
  }
}

TEST(WilsonInterval, NoSuccessesStartsAtZeroAndAllSuccessesEndAtOne) {
  for (const double n : {1.0, 2.0, 10.0, 1000.0}) {
    const Interval none = wilson_interval(0, n);
    EXPECT_EQ(none.low, 0.0);
    EXPECT_GT(none.high, 0.0);
    EXPECT_LT(none.high, 1.0);
    const Interval all = wilson_interval(n, n);
    EXPECT_EQ(all.high, 1.0);
    EXPECT_GT(all.low, 0.0);
    EXPECT_LT(all.low, 1.0);
  }
  // 0 of n: the upper bound is z²/(n + z²).
  const double z = normal_quantile(0.95);
  EXPECT_NEAR(wilson_interval(0, 10).high, z * z / (10 + z * z), 1e-12);
}

TEST(WilsonInterval, NoTrialsGivesTheWholeUnitInterval) {
  const Interval i = wilson_interval(0, 0);
  EXPECT_EQ(i.low, 0.0);
  EXPECT_EQ(i.high, 1.0);
}

TEST(WilsonInterval, IsSymmetricUnderSwappingSuccessesAndFailures) {
  for (const double n : {5.0, 12.0, 101.0}) {
    for (double k = 0; k <= n; ++k) {
      const Interval a = wilson_interval(k, n);
      const Interval b = wilson_interval(n - k, n);
      EXPECT_NEAR(a.low, 1.0 - b.high, 1e-12) << k << " of " << n;
      EXPECT_NEAR(a.high, 1.0 - b.low, 1e-12) << k << " of " << n;
    }
  }
}

TEST(WilsonInterval, ContainsTheObservedRate) {
  for (double k = 0; k <= 17; ++k) {
    const Interval i = wilson_interval(k, 17);
    EXPECT_LE(i.low, k / 17);
    EXPECT_GE(i.high, k / 17);
  }
}

TEST(WilsonInterval, NarrowsMonotonicallyAsTrialsGrowAtFixedRate) {
  for (const double rate : {0.0, 0.25, 0.5, 0.8, 1.0}) {
    double previous = 1.0;
    for (double n = 4; n <= 4096; n *= 2) {
      const double width = wilson_interval(rate * n, n).half_width();
      EXPECT_LT(width, previous) << "rate " << rate << ", n " << n;
      previous = width;
    }
  }
}

TEST(WilsonInterval, WidensWithConfidence) {
  EXPECT_LT(wilson_interval(8, 10, 0.90).half_width(), wilson_interval(8, 10, 0.95).half_width());
  EXPECT_LT(wilson_interval(8, 10, 0.95).half_width(), wilson_interval(8, 10, 0.99).half_width());
}

TEST(WilsonInterval, AcceptsFractionalEffectiveCounts) {
  const Interval i = wilson_interval(6.5, 7.25);
  EXPECT_LT(i.low, 6.5 / 7.25);
  EXPECT_GT(i.high, 6.5 / 7.25);
}

TEST(WilsonInterval, RejectsImpossibleCountsAndConfidences) {
  EXPECT_THROW((void)wilson_interval(11, 10), std::invalid_argument);
  EXPECT_THROW((void)wilson_interval(-1, 10), std::invalid_argument);
  EXPECT_THROW((void)wilson_interval(0, -1), std::invalid_argument);
  EXPECT_THROW((void)wilson_interval(1, 10, 0.0), std::invalid_argument);
  EXPECT_THROW((void)wilson_interval(1, 10, 1.0), std::invalid_argument);
  EXPECT_THROW((void)wilson_interval(0, 0, 1.5), std::invalid_argument);
}

TEST(WilsonWorstCase, EqualsTheLargestHalfWidthOverEveryOutcome) {
  const double z = normal_quantile(0.95);
  for (const int n : {1, 2, 3, 4, 9, 10, 25, 50, 99, 100, 1000}) {
    double largest = 0.0;
    for (int k = 0; k <= n; ++k) largest = std::max(largest, wilson_interval(k, n).half_width());
    const double worst = wilson_worst_half_width(n);
    EXPECT_NEAR(worst, z / (2 * std::sqrt(n + z * z)), 1e-15);
    if (n % 2 == 0) {
      // p̂ = ½ is an outcome: the bound is attained.
      EXPECT_NEAR(worst, largest, 1e-12) << "n " << n;
    } else {
      // p̂ = ½ is not an outcome: the bound is the supremum over p̂, just above every outcome.
      EXPECT_GE(worst, largest) << "n " << n;
      EXPECT_NEAR(worst, largest, 0.5 / (n * n) + 1e-12) << "n " << n;
    }
  }
}

TEST(WilsonWorstCase, SampleSizeIsTheSmallestSufficientN) {
  for (const double confidence : {0.9, 0.95, 0.99}) {
    for (const double epsilon : {0.01, 0.05, 0.1, 0.15, 0.2, 0.25, 0.3, 0.45}) {
      const std::size_t n = wilson_sample_size(epsilon, confidence);
      ASSERT_GE(n, 1U);
      EXPECT_LE(wilson_worst_half_width(static_cast<double>(n), confidence), epsilon);
      if (n > 1) {
        EXPECT_GT(wilson_worst_half_width(static_cast<double>(n - 1), confidence), epsilon);
      }
      const double z = normal_quantile(confidence);
      EXPECT_EQ(n, static_cast<std::size_t>(std::max(1.0, std::ceil(z * z / (4 * epsilon * epsilon) - z * z))));
    }
  }
}

TEST(WilsonWorstCase, SampleSizeRejectsEpsilonOutsideTheOpenHalfInterval) {
  EXPECT_THROW((void)wilson_sample_size(0.0), std::invalid_argument);
  EXPECT_THROW((void)wilson_sample_size(0.5), std::invalid_argument);
  EXPECT_THROW((void)wilson_sample_size(-0.1), std::invalid_argument);
  EXPECT_THROW((void)wilson_sample_size(0.1, 1.0), std::invalid_argument);
}

TEST(Hoeffding, PerCellSampleSizeIsTheProposition) {
  EXPECT_EQ(hoeffding_sample_size(0.1, 0.05), 185U);  // ln(40)/0.02 = 184.4
  for (const double epsilon : {0.02, 0.05, 0.1, 0.25, 0.4}) {
    for (const double delta : {0.01, 0.05, 0.1, 0.5}) {
      EXPECT_EQ(hoeffding_sample_size(epsilon, delta),
                static_cast<std::size_t>(std::ceil(std::log(2 / delta) / (2 * epsilon * epsilon))));
    }
  }
}

TEST(Hoeffding, EpsilonInvertsTheSampleSize) {
  for (const double epsilon : {0.02, 0.05, 0.1, 0.25, 0.4}) {
    for (const double delta : {0.01, 0.05, 0.1, 0.5}) {
      const std::size_t n = hoeffding_sample_size(epsilon, delta);
      EXPECT_LE(hoeffding_epsilon(static_cast<double>(n), delta), epsilon * (1 + 1e-12));
      if (n > 1) {
        EXPECT_GT(hoeffding_epsilon(static_cast<double>(n - 1), delta), epsilon);
      }
      // ... and the probability bound at that ε is δ.
      const double e = hoeffding_epsilon(static_cast<double>(n), delta);
      EXPECT_NEAR(hoeffding_probability(static_cast<double>(n), e), delta, 1e-12);
    }
  }
}

TEST(Hoeffding, ProbabilityIsTheCappedExponentialBound) {
  EXPECT_NEAR(hoeffding_probability(100, 0.1), 2 * std::exp(-2.0), 1e-15);
  EXPECT_EQ(hoeffding_probability(0, 0.1), 1.0);
  EXPECT_EQ(hoeffding_probability(1, 0.01), 1.0);
  EXPECT_LT(hoeffding_probability(1000, 0.1), hoeffding_probability(100, 0.1));
}

TEST(Hoeffding, RejectsInvalidArguments) {
  EXPECT_THROW((void)hoeffding_sample_size(0.0, 0.05), std::invalid_argument);
  EXPECT_THROW((void)hoeffding_sample_size(-0.1, 0.05), std::invalid_argument);
  EXPECT_THROW((void)hoeffding_sample_size(0.1, 0.0), std::invalid_argument);
  EXPECT_THROW((void)hoeffding_sample_size(0.1, 1.0), std::invalid_argument);
  EXPECT_THROW((void)hoeffding_epsilon(10, 0.0), std::invalid_argument);
  EXPECT_THROW((void)hoeffding_epsilon(-1, 0.05), std::invalid_argument);
  EXPECT_THROW((void)hoeffding_probability(-1, 0.1), std::invalid_argument);
  EXPECT_THROW((void)hoeffding_probability(10, -0.1), std::invalid_argument);
}

TEST(StatisticsWeightedSuccess, EqualWeightsGiveThePlainSuccessRate) {
  const std::vector<double> weights(8, 2.5);
  const std::vector<int> outcomes{1, 1, 0, 1, 1, 1, 0, 1};
  const WeightedEstimate e = weighted_success(weights, outcomes);
  EXPECT_NEAR(e.estimate, 6.0 / 8.0, 1e-15);
  EXPECT_EQ(e.n, 8U);
  EXPECT_NEAR(e.weight, 20.0, 1e-12);
  EXPECT_NEAR(e.n_eff, 8.0, 1e-12);
  const Interval plain = wilson_interval(6, 8);
  EXPECT_NEAR(e.wilson.low, plain.low, 1e-12);
  EXPECT_NEAR(e.wilson.high, plain.high, 1e-12);
}

TEST(StatisticsWeightedSuccess, WeightsGiveTheRatioOfWeightedSums) {
  const std::vector<double> weights{0.5, 2.0, 1.0, 4.0, 0.25};
  const std::vector<int> outcomes{1, 0, 1, 1, 0};
  const WeightedEstimate e = weighted_success(weights, outcomes);
  EXPECT_NEAR(e.estimate, (0.5 + 1.0 + 4.0) / 7.75, 1e-15);
  EXPECT_NEAR(e.weight, 7.75, 1e-15);
  EXPECT_NEAR(e.n_eff, 7.75 * 7.75 / (0.25 + 4 + 1 + 16 + 0.0625), 1e-12);
  EXPECT_LT(e.n_eff, 5.0);
  const Interval at_n_eff = wilson_interval(e.n_eff * e.estimate, e.n_eff);
  EXPECT_NEAR(e.wilson.low, at_n_eff.low, 1e-12);
  EXPECT_NEAR(e.wilson.high, at_n_eff.high, 1e-12);
}

TEST(StatisticsWeightedSuccess, AllSuccessesReachOneDespiteRounding) {
  const std::vector<double> weights{0.1, 0.7, 0.3, 1.9};
  const std::vector<int> outcomes{1, 1, 1, 1};
  const WeightedEstimate e = weighted_success(weights, outcomes);
  EXPECT_EQ(e.estimate, 1.0);
  EXPECT_EQ(e.wilson.high, 1.0);
}

TEST(StatisticsWeightedSuccess, EmptySetHasNoEstimate) {
  const WeightedEstimate e = weighted_success({}, {});
  EXPECT_TRUE(std::isnan(e.estimate));
  EXPECT_EQ(e.n, 0U);
  EXPECT_EQ(e.weight, 0.0);
  EXPECT_EQ(e.n_eff, 0.0);
  EXPECT_EQ(e.wilson.low, 0.0);
  EXPECT_EQ(e.wilson.high, 1.0);
}

TEST(StatisticsWeightedSuccess, RejectsMismatchedOrInvalidInput) {
  const std::vector<double> two{1.0, 1.0};
  const std::vector<int> three{1, 0, 1};
  EXPECT_THROW((void)weighted_success(two, three), std::invalid_argument);
  const std::vector<int> ok{1, 0};
  const std::vector<double> negative{1.0, -0.5};
  EXPECT_THROW((void)weighted_success(negative, ok), std::invalid_argument);
  const std::vector<double> infinite{1.0, INFINITY};
  EXPECT_THROW((void)weighted_success(infinite, ok), std::invalid_argument);
  const std::vector<double> nan{std::nan(""), 1.0};
  EXPECT_THROW((void)weighted_success(nan, ok), std::invalid_argument);
  const std::vector<int> not_binary{1, 2};
  EXPECT_THROW((void)weighted_success(two, not_binary), std::invalid_argument);
}

TEST(StatisticsEffectiveSampleSize, IsKishsFormula) {
  const std::vector<double> equal(12, 0.3);
  EXPECT_NEAR(effective_sample_size(equal), 12.0, 1e-12);
  const std::vector<double> unequal{1.0, 2.0, 3.0, 10.0};
  EXPECT_NEAR(effective_sample_size(unequal), 16.0 * 16.0 / 114.0, 1e-12);
  EXPECT_LT(effective_sample_size(unequal), 4.0);
  EXPECT_GE(effective_sample_size(unequal), 1.0);
  EXPECT_EQ(effective_sample_size({}), 0.0);
  const std::vector<double> one_dominant{1e-9, 1e-9, 1.0};
  EXPECT_NEAR(effective_sample_size(one_dominant), 1.0, 1e-6);
}

}  // namespace statistics_test
}  // namespace emrm::scenario
