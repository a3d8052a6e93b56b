#pragma once
// Summary statistics of repetition times. Pure functions; no I/O.
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

}  // namespace suite
