#include "harness/common/stats.hpp"

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


double robust_relative_spread(std::vector<double> s) {
    if (s.size() < 2) return 0;
    auto median_of = [](std::vector<double>& v) {
        const std::size_t n = v.size();
        std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(n / 2), v.end());
        const double hi = v[n / 2];
        if (n % 2) return hi;
        return 0.5 * (hi + *std::max_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(n / 2)));
    };
    const double med = median_of(s);
    if (!(med > 0)) return 0;
    for (double& x : s) x = std::fabs(x - med);
    return 1.4826 * median_of(s) / med;
}

}  // namespace suite
