#include "harness/stats.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>

namespace suite {

TimeStats summarise(std::vector<double> s) {
    if (s.empty()) throw std::invalid_argument("summarise: no samples");
    std::sort(s.begin(), s.end());
    TimeStats t;
    const std::size_t n = s.size();
    t.min = s.front();
    t.max = s.back();
    t.median = n % 2 ? s[n / 2] : 0.5 * (s[n / 2 - 1] + s[n / 2]);
    t.mean = std::accumulate(s.begin(), s.end(), 0.0) / static_cast<double>(n);
    double ss = 0;
    for (double x : s) ss += (x - t.mean) * (x - t.mean);
    t.cv = n > 1 && t.mean > 0 ? std::sqrt(ss / static_cast<double>(n - 1)) / t.mean : 0.0;
    return t;
}

}  // namespace suite
