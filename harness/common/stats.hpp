#pragma once
// Summary statistics of repetition times, and the tests that compare two sets of them. Pure
// functions; no I/O.
#include <vector>

namespace suite {

struct TimeStats {
    double min = 0, median = 0, max = 0, mean = 0;
    double cv = 0;  // coefficient of variation: sample standard deviation / mean
};

// Throws std::invalid_argument on an empty sample.
TimeStats summarise(std::vector<double> seconds);

// Robust relative spread of samples: 1.4826 * median absolute deviation / median (the standard
// deviation for normal noise, unmoved by a few outliers); 0 for fewer than 2 samples.
double robust_relative_spread(std::vector<double> samples);

// The Mann–Whitney U test (Wilcoxon rank-sum) of two independent samples: does one tend to be
// larger than the other? p_x_smaller is the one-sided p-value for "x tends to be smaller than y"
// (e.g. the run's times are smaller: faster), p_x_larger the other side. Exact (by counting the
// rank arrangements) when both samples have at most 30 values and no ties; otherwise the normal
// approximation with the tie correction and a continuity correction. Empty samples give p = 1.
struct RankTest {
    double u = 0;  // U of x: the number of (x, y) pairs with x > y, a tie counting one half
    double p_x_smaller = 1, p_x_larger = 1;
    bool exact = false;
};
RankTest mann_whitney(const std::vector<double>& x, const std::vector<double>& y);

// A percentile bootstrap interval of median(y) / median(x): both samples resampled with
// replacement `resamples` times from a fixed seed (the same inputs give the same interval).
// estimate is the ratio of the samples' own medians. Throws std::invalid_argument on an empty
// sample or a median of x that is not positive.
struct Interval {
    double low = 0, estimate = 0, high = 0;
};
Interval median_ratio_interval(const std::vector<double>& x, const std::vector<double>& y, double level = 0.95,
                               unsigned resamples = 2000, unsigned long long seed = 1);

// The median of a sample (the mean of the middle two for an even count); throws on an empty one.
double median_of(std::vector<double> s);

}  // namespace suite
