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
    const double med = median_of(s);
    if (!(med > 0)) return 0;
    for (double& x : s) x = std::fabs(x - med);
    return 1.4826 * median_of(s) / med;
}

double median_of(std::vector<double> s) {
    if (s.empty()) throw std::invalid_argument("median: no samples");
    const std::size_t n = s.size();
    std::nth_element(s.begin(), s.begin() + static_cast<std::ptrdiff_t>(n / 2), s.end());
    const double hi = s[n / 2];
    if (n % 2) return hi;
    return 0.5 * (hi + *std::max_element(s.begin(), s.begin() + static_cast<std::ptrdiff_t>(n / 2)));
}

namespace {

// The number of arrangements of m x-values among m + n ranks whose U (pairs with x > y) is u,
// for every u: the classic recurrence c(m, n, u) = c(m - 1, n, u - n) + c(m, n - 1, u), by rows.
std::vector<double> u_counts(std::size_t m, std::size_t n) {
    // table[j][u] for the current i (x values placed) and j (y values placed).
    std::vector<std::vector<double>> prev(n + 1), cur(n + 1);
    for (std::size_t j = 0; j <= n; ++j) prev[j] = {1.0};  // i = 0: U is 0 whatever j is
    for (std::size_t i = 1; i <= m; ++i) {
        cur[0] = {1.0};  // no y: U is 0
        for (std::size_t j = 1; j <= n; ++j) {
            // The largest value is an x (it beats all j y's: U grows by j) or a y (U unchanged).
            std::vector<double> c(i * j + 1, 0.0);
            for (std::size_t u = 0; u < prev[j].size(); ++u) c[u + j] += prev[j][u];
            for (std::size_t u = 0; u < cur[j - 1].size(); ++u) c[u] += cur[j - 1][u];
            cur[j] = std::move(c);
        }
        std::swap(prev, cur);
    }
    return prev[n];
}

double normal_upper_tail(double z) { return 0.5 * std::erfc(z / std::sqrt(2.0)); }

}  // namespace

RankTest mann_whitney(const std::vector<double>& x, const std::vector<double>& y) {
    RankTest t;
    const std::size_t m = x.size(), n = y.size();
    if (m == 0 || n == 0) return t;
    // Ranks of the pooled sample, ties given their average rank.
    std::vector<std::pair<double, int>> all;
    for (double v : x) all.push_back({v, 0});
    for (double v : y) all.push_back({v, 1});
    std::sort(all.begin(), all.end());
    double rank_sum_x = 0, tie_term = 0;
    bool ties = false;
    for (std::size_t i = 0; i < all.size();) {
        std::size_t j = i;
        while (j < all.size() && all[j].first == all[i].first) ++j;
        const double avg_rank = 0.5 * static_cast<double>(i + 1 + j);  // ranks i+1 .. j
        const double k = static_cast<double>(j - i);
        if (k > 1) ties = true;
        tie_term += k * k * k - k;
        for (std::size_t q = i; q < j; ++q)
            if (all[q].second == 0) rank_sum_x += avg_rank;
        i = j;
    }
    const double md = static_cast<double>(m), nd = static_cast<double>(n);
    t.u = rank_sum_x - md * (md + 1) / 2;
    if (!ties && m <= 30 && n <= 30) {
        const std::vector<double> c = u_counts(m, n);
        double total = 0, at_most = 0, at_least = 0;
        const auto u = static_cast<std::size_t>(std::llround(t.u));
        for (std::size_t k = 0; k < c.size(); ++k) {
            total += c[k];
            if (k <= u) at_most += c[k];
            if (k >= u) at_least += c[k];
        }
        t.p_x_smaller = at_most / total;
        t.p_x_larger = at_least / total;
        t.exact = true;
        return t;
    }
    const double mean = md * nd / 2;
    const double var = md * nd / 12 * ((md + nd + 1) - tie_term / ((md + nd) * (md + nd - 1)));
    if (!(var > 0)) return t;  // every value equal: nothing tells the samples apart
    const double sd = std::sqrt(var);
    // The lower tail as an upper tail of -z: 1 - upper(z) would round a small p to 0.
    t.p_x_smaller = normal_upper_tail(-(t.u + 0.5 - mean) / sd);
    t.p_x_larger = normal_upper_tail((t.u - 0.5 - mean) / sd);
    return t;
}

Interval median_ratio_interval(const std::vector<double>& x, const std::vector<double>& y, double level,
                               unsigned resamples, unsigned long long seed) {
    if (x.empty() || y.empty()) throw std::invalid_argument("median_ratio_interval: an empty sample");
    Interval r;
    const double mx = median_of(x);
    if (!(mx > 0)) throw std::invalid_argument("median_ratio_interval: the first sample's median is not positive");
    r.estimate = median_of(y) / mx;
    // splitmix64: a small, fixed generator, so that an interval is the same on every machine.
    unsigned long long state = seed;
    auto next = [&state]() {
        unsigned long long z = (state += 0x9E3779B97F4A7C15ULL);
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
        return z ^ (z >> 31);
    };
    auto resample = [&](const std::vector<double>& s, std::vector<double>& out) {
        out.resize(s.size());
        for (double& v : out) v = s[next() % s.size()];
        return median_of(out);
    };
    std::vector<double> ratios, bx, by;
    ratios.reserve(resamples);
    for (unsigned k = 0; k < resamples; ++k) {
        const double dx = resample(x, bx);
        if (dx > 0) ratios.push_back(resample(y, by) / dx);
    }
    if (ratios.empty()) return {r.estimate, r.estimate, r.estimate};
    std::sort(ratios.begin(), ratios.end());
    const double tail = (1 - level) / 2;
    auto at = [&](double q) {
        const auto i = static_cast<std::size_t>(
            std::clamp(q * static_cast<double>(ratios.size() - 1), 0.0, static_cast<double>(ratios.size() - 1)));
        return ratios[i];
    };
    r.low = at(tail);
    r.high = at(1 - tail);
    return r;
}

}  // namespace suite
