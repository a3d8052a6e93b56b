// The summary statistics of repetition times.
#include <gtest/gtest.h>

#include "harness/common/stats.hpp"

using namespace suite;

TEST(Stats, SummaryOfKnownSample) {
    TimeStats s = summarise({4.0, 1.0, 3.0, 2.0});
    EXPECT_DOUBLE_EQ(s.min, 1.0);
    EXPECT_DOUBLE_EQ(s.max, 4.0);
    EXPECT_DOUBLE_EQ(s.median, 2.5);
    EXPECT_DOUBLE_EQ(s.mean, 2.5);
    EXPECT_NEAR(s.cv, 1.2909944487358056 / 2.5, 1e-12);  // sample standard deviation / mean
    EXPECT_DOUBLE_EQ(summarise({7.0}).cv, 0.0);
    EXPECT_THROW(summarise({}), std::invalid_argument);
}

// Reference p-values from SciPy 1.10's mannwhitneyu (method "exact" without ties; "asymptotic"
// with the continuity correction where there are ties or a sample has more than 30 values).
TEST(Stats, MannWhitneyExactMatchesTheReference) {
    const std::vector<double> x{1.1, 2.3, 2.9, 4.0, 5.5}, y{3.0, 6.1, 7.2, 8.8, 9.0, 10.5};
    RankTest t = mann_whitney(x, y);
    EXPECT_TRUE(t.exact);
    EXPECT_DOUBLE_EQ(t.u, 2.0);
    EXPECT_NEAR(t.p_x_smaller, 0.008658008658008658, 1e-12);
    EXPECT_NEAR(t.p_x_larger, 0.9956709956709957, 1e-12);
    // Swapping the samples swaps the sides.
    RankTest s = mann_whitney(y, x);
    EXPECT_NEAR(s.p_x_larger, t.p_x_smaller, 1e-12);
    // Five against five, fully separated: the smallest p there is, 1 / C(10, 5).
    EXPECT_NEAR(mann_whitney({1, 2, 3, 4, 5}, {6, 7, 8, 9, 10}).p_x_smaller, 1.0 / 252, 1e-12);
}

TEST(Stats, MannWhitneyWithTiesAndLargeSamplesUsesTheNormalApproximation) {
    RankTest t = mann_whitney({1, 2, 2, 3, 3, 3, 4, 5}, {3, 4, 4, 5, 5, 6, 7, 7, 8});
    EXPECT_FALSE(t.exact);
    EXPECT_DOUBLE_EQ(t.u, 7.5);
    EXPECT_NEAR(t.p_x_smaller, 0.0031865669190429364, 1e-9);
    EXPECT_NEAR(t.p_x_larger, 0.9976386658073535, 1e-9);
    std::vector<double> x, y;
    for (int i = 0; i < 40; ++i) x.push_back(1 + i / 39.0);
    for (int i = 0; i < 35; ++i) y.push_back(1.5 + i / 34.0);
    RankTest big = mann_whitney(x, y);
    EXPECT_FALSE(big.exact);
    EXPECT_DOUBLE_EQ(big.u, 185.5);
    EXPECT_NEAR(big.p_x_smaller, 2.3987118388806916e-08, 1e-12);
}

TEST(Stats, MannWhitneyOfIdenticalOrEmptySamplesFindsNothing) {
    RankTest same = mann_whitney({2, 2, 2}, {2, 2, 2});
    EXPECT_DOUBLE_EQ(same.p_x_smaller, 1.0);
    EXPECT_DOUBLE_EQ(same.p_x_larger, 1.0);
    EXPECT_DOUBLE_EQ(mann_whitney({}, {1, 2}).p_x_smaller, 1.0);
}

TEST(Stats, MedianRatioIntervalHoldsTheEstimateAndIsReproducible) {
    const std::vector<double> x{1.00, 1.02, 0.98, 1.01, 0.99, 1.03, 0.97}, y{1.50, 1.52, 1.49, 1.55, 1.48, 1.51, 1.53};
    Interval a = median_ratio_interval(x, y), b = median_ratio_interval(x, y);
    EXPECT_DOUBLE_EQ(a.estimate, 1.51 / 1.00);
    EXPECT_LE(a.low, a.estimate);
    EXPECT_GE(a.high, a.estimate);
    EXPECT_GT(a.low, 1.4);  // far from 1: the samples do not overlap
    EXPECT_LT(a.high, 1.6);
    EXPECT_DOUBLE_EQ(a.low, b.low);  // a fixed seed: the same interval every time
    EXPECT_DOUBLE_EQ(a.high, b.high);
    // Wider noise, wider interval.
    Interval wide = median_ratio_interval({0.5, 1.5, 1.0, 0.7, 1.3}, {0.6, 1.6, 1.1, 0.8, 1.4});
    EXPECT_GT(wide.high - wide.low, 5 * (a.high - a.low));
    EXPECT_THROW(median_ratio_interval({}, {1}), std::invalid_argument);
    EXPECT_THROW(median_ratio_interval({0, 0, 0}, {1}), std::invalid_argument);
}

TEST(Stats, MedianOf) {
    EXPECT_DOUBLE_EQ(median_of({3, 1, 2}), 2.0);
    EXPECT_DOUBLE_EQ(median_of({4, 1, 3, 2}), 2.5);
    EXPECT_THROW(median_of({}), std::invalid_argument);
}
