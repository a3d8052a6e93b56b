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
