#include "harness/results/history_pool.hpp"

#include <algorithm>
#include <map>

#include <boost/math/distributions/chi_squared.hpp>
#include <boost/math/distributions/normal.hpp>
#include <boost/math/special_functions/digamma.hpp>
#include <boost/math/special_functions/trigamma.hpp>

#include "harness/common/stats.hpp"
#include "harness/results/history_scale.hpp"

namespace suite {

namespace {

constexpr double residual_clip = 2.5;
// The weight given to the machine's spread is taken at the low end of what the series allow (below).
constexpr double prior_quantile = 0.25;

// y > 0 with trigamma(y) = x (trigamma falls from infinity to 0), by bisection on log y.
double trigamma_inverse(double x) {
    double lo = std::log(1e-6), hi = std::log(1e8);
    for (int i = 0; i < 200 && hi - lo > 1e-10; ++i) {
        const double mid = (lo + hi) / 2;
        (boost::math::trigamma(std::exp(mid)) > x ? lo : hi) = mid;
    }
    return std::exp((lo + hi) / 2);
}

struct Fit {
    std::size_t index;
    double log_var, df;
    std::map<std::int64_t, double> residual;  // by run: (log median - centre) / own spread, clipped
};

// The fit of one window: its own spread and each run's residual; false where the window has
// fewer than `min_runs` medians, one that is not positive, or no spread (an exact count).
bool fit_window(const SeriesWindow& w, std::size_t index, std::size_t min_runs, ScaleEstimate& q, Fit& f) {
    if (w.medians.size() < std::max<std::size_t>(min_runs, 2)) return false;
    std::vector<double> logs;
    for (double m : w.medians)
        if (m > 0 && std::isfinite(m)) logs.push_back(std::log(m));
    if (logs.size() != w.medians.size()) return false;
    q = qn_scale(logs);
    if (!(q.sigma > 0)) return false;
    f = Fit{index, std::log(q.sigma * q.sigma), q.df, {}};
    const double centre = median_of(logs);
    for (std::size_t k = 0; k < logs.size() && k < w.runs.size(); ++k)
        f.residual[w.runs[k]] = std::clamp((logs[k] - centre) / q.sigma, -residual_clip, residual_clip);
    return true;
}

// The correlation of two series' residuals over the runs they share (NAN: fewer than 3, or one
// that never moves), and how many runs that was.
double residual_correlation(const Fit& a, const Fit& b, std::size_t& shared_runs) {
    double ab = 0, aa = 0, bb = 0;
    std::size_t k = 0;
    for (const auto& [run, x] : a.residual) {
        const auto it = b.residual.find(run);
        if (it == b.residual.end()) continue;
        ab += x * it->second;
        aa += x * x;
        bb += it->second * it->second;
        ++k;
    }
    shared_runs = k;
    if (k < 3 || !(aa > 0 && bb > 0)) return NAN;
    return ab / std::sqrt(aa * bb);
}

// The squared correlation of two series' residuals over the runs they share, adjusted for the
// upward bias of r^2 on k pairs (1 - (1 - r^2)(k - 1)/(k - 2)); r itself in `r`. Fewer than 3
// shared runs: 1 (nothing says they are apart).
double squared_correlation(const Fit& a, const Fit& b, double& r) {
    std::size_t k = 0;
    r = residual_correlation(a, b, k);
    if (k < 3) return 1;
    if (!std::isfinite(r)) return 0;
    const double kk = static_cast<double>(k);
    return std::clamp(1 - (1 - r * r) * (kk - 1) / (kk - 2), 0.0, 1.0);
}

void find_jumps(const std::vector<SeriesWindow>& windows, std::size_t min_runs, MachineNoise& out) {
    for (std::size_t i = 0; i < windows.size(); ++i) {
        const SeriesWindow& w = windows[i];
        const double sigma = out.series[i].sigma;
        if (!(sigma > 0) || w.medians.size() < std::max<std::size_t>(min_runs, 3)) continue;
        std::vector<double> logs;
        for (double m : w.medians)
            if (m > 0 && std::isfinite(m)) logs.push_back(std::log(m));
        if (logs.size() != w.medians.size()) continue;
        const double n = static_cast<double>(logs.size());
        const double limit = jump_sigmas * sigma * std::sqrt(1 + std::acos(-1.0) / (2 * (n - 1)));
        for (std::size_t k = 0; k < logs.size(); ++k) {
            std::vector<double> others = logs;
            others.erase(others.begin() + static_cast<std::ptrdiff_t>(k));
            const double d = std::fabs(logs[k] - median_of(others));
            ++out.jump_runs;
            if (d > limit) out.jumps.push_back(d);
        }
    }
    const double rate = out.jump_runs ? static_cast<double>(out.jumps.size()) / static_cast<double>(out.jump_runs) : 0;
    // What every band of the figure mixes in (RunBand::half_for), sorted, once: at most 32 jumps,
    // each standing for its share of the rest (their quantiles), so that a long history of a
    // noisy machine does not cost a bisection over hundreds of them for every band.
    std::vector<double> mixed = out.jumps;
    std::sort(mixed.begin(), mixed.end());
    if (mixed.size() > 32) {
        std::vector<double> q;
        for (std::size_t i = 0; i < 32; ++i) q.push_back(mixed[(2 * i + 1) * mixed.size() / 64]);
        mixed = std::move(q);
    }
    std::vector<double> spreads;
    for (const PooledSpread& p : out.series)
        if (p.sigma > 0) spreads.push_back(p.sigma);
    const double typical = spreads.empty() ? 0 : median_of(spreads);
    for (PooledSpread& p : out.series)
        if (std::isfinite(p.sigma)) {
            p.jumps = mixed;
            p.jump_rate = rate;
            p.jump_spread = typical;
        }
}

// The pooling proper (history_pool.hpp), without the jumps.
MachineNoise pool_only(const std::vector<SeriesWindow>& windows, std::size_t min_runs) {
    MachineNoise out;
    out.series.resize(windows.size());
    std::vector<Fit> fits;
    for (std::size_t i = 0; i < windows.size(); ++i) {
        const SeriesWindow& w = windows[i];
        ScaleEstimate q;
        Fit f;
        const bool fitted = fit_window(w, i, min_runs, q, f);
        if (!std::isfinite(q.sigma)) continue;
        PooledSpread& p = out.series[i];
        p.own = p.sigma = q.sigma;
        p.own_df = p.df = q.df;
        // A series that never moves (an exact count) says nothing about the machine's noise.
        if (fitted) fits.push_back(std::move(f));
    }
    const std::size_t s = fits.size();
    if (s < 3) return out;
    // The prior by moments of log s^2: each minus its expectation given sigma, whose variance
    // beyond the sampling part, trigamma(d / 2), is the spread of the series' true log variances.
    double mean_e = 0, sampling = 0, mean_df = 0;
    std::vector<double> e;
    for (const Fit& f : fits) {
        e.push_back(f.log_var - boost::math::digamma(f.df / 2) + std::log(f.df / 2));
        mean_e += e.back();
        sampling += boost::math::trigamma(f.df / 2);
        mean_df += f.df;
    }
    const double sd = static_cast<double>(s);
    mean_e /= sd;
    sampling /= sd;
    mean_df /= sd;
    double var_e = 0;
    for (double x : e) var_e += (x - mean_e) * (x - mean_e);
    var_e /= sd - 1;
    // The variance of the true log variances: its estimate places the prior (s0), and its 75 %
    // upper bound, var_e (S - 1) / chi^2_{S-1}(0.25), weighs it (d0). Four series whose spreads
    // happen to look alike say little about how alike they are: weighed at the estimate, the
    // noisiest of four series of 2 to 6 % was pulled toward the others and its band left 12 % of
    // unchanged runs out at a 5 % alpha; at the bound, 10 %, and the four together 6 %
    // (tests/results/history_pool_test.cpp).
    const boost::math::chi_squared chi(sd - 1);
    const double excess = var_e - sampling;
    const double excess_high = var_e * (sd - 1) / boost::math::quantile(chi, prior_quantile) - sampling;
    const double d0_point = excess > 0 ? 2 * trigamma_inverse(excess) : INFINITY;
    const double d0_fitted = excess_high > 0 ? 2 * trigamma_inverse(excess_high) : INFINITY;
    // E[log s^2] = log sigma0^2 + digamma(d0 / 2) - log(d0 / 2) under the prior (0 as d0 grows).
    const double log_s0 =
        mean_e + (std::isfinite(d0_point) ? boost::math::digamma(d0_point / 2) - std::log(d0_point / 2) : 0);
    // The cap: the other series' degrees of freedom, as many as their correlation leaves.
    double rho2 = 0, rho = 0;
    std::size_t pairs = 0, measured = 0;
    for (std::size_t a = 0; a < s; ++a)
        for (std::size_t b = a + 1; b < s; ++b) {
            double r;
            rho2 += squared_correlation(fits[a], fits[b], r);
            ++pairs;
            if (std::isfinite(r)) {
                rho += r;
                ++measured;
            }
        }
    rho2 /= static_cast<double>(pairs);
    out.shared = measured ? rho / static_cast<double>(measured) : NAN;
    out.effective_series = sd / (1 + (sd - 1) * rho2);
    const double others = (sd - 1) / (1 + (sd - 2) * rho2);
    const double d0 = std::min(d0_fitted, mean_df * others);
    out.prior = std::exp(log_s0 / 2);
    out.prior_df = d0;
    const double s0 = out.prior * out.prior;
    for (const Fit& f : fits) {
        PooledSpread& p = out.series[f.index];
        p.sigma = std::sqrt((d0 * s0 + f.df * p.own * p.own) / (d0 + f.df));
        p.df = d0 + f.df;
    }
    return out;
}

}  // namespace

double MachineNoise::largest_jump() const { return jumps.empty() ? 0 : *std::max_element(jumps.begin(), jumps.end()); }

MachineNoise pool_spreads(const std::vector<SeriesWindow>& windows, std::size_t min_runs) {
    MachineNoise out = pool_only(windows, min_runs);
    find_jumps(windows, min_runs, out);
    return out;
}

namespace {

// The eigenvalues of a small symmetric matrix (row-major, n x n), by cyclic Jacobi rotations:
// a point's handful of figures, so a few sweeps of n^2 rotations each.
std::vector<double> symmetric_eigenvalues(std::vector<double> a, std::size_t n) {
    for (int sweep = 0; sweep < 50; ++sweep) {
        double off = 0;
        for (std::size_t p = 0; p < n; ++p)
            for (std::size_t q = p + 1; q < n; ++q) off += a[p * n + q] * a[p * n + q];
        if (off < 1e-24) break;
        for (std::size_t p = 0; p < n; ++p)
            for (std::size_t q = p + 1; q < n; ++q) {
                const double apq = a[p * n + q];
                if (std::fabs(apq) < 1e-300) continue;
                const double theta = (a[q * n + q] - a[p * n + p]) / (2 * apq);
                const double t = (theta >= 0 ? 1 : -1) / (std::fabs(theta) + std::sqrt(theta * theta + 1));
                const double c = 1 / std::sqrt(t * t + 1), sn = t * c;
                for (std::size_t k = 0; k < n; ++k) {  // columns p and q
                    const double akp = a[k * n + p], akq = a[k * n + q];
                    a[k * n + p] = c * akp - sn * akq;
                    a[k * n + q] = sn * akp + c * akq;
                }
                for (std::size_t k = 0; k < n; ++k) {  // rows p and q
                    const double apk = a[p * n + k], aqk = a[q * n + k];
                    a[p * n + k] = c * apk - sn * aqk;
                    a[q * n + k] = sn * apk + c * aqk;
                }
            }
    }
    std::vector<double> out(n);
    for (std::size_t i = 0; i < n; ++i) out[i] = a[i * n + i];
    return out;
}

}  // namespace

double effective_figures(const std::vector<std::vector<SeriesWindow>>& points, std::size_t min_runs) {
    const double z = -boost::math::quantile(boost::math::normal(), prior_quantile);
    double total = 0;
    for (const auto& figures : points) {
        const std::size_t n = figures.size();
        if (n == 0) continue;
        std::vector<Fit> fits(n);
        std::vector<bool> fitted(n);
        for (std::size_t i = 0; i < n; ++i) {
            ScaleEstimate q;
            fitted[i] = fit_window(figures[i], i, min_runs, q, fits[i]);
        }
        // The correlation matrix, each r at its lower bound in size (Fisher's z, one-sided at
        // 1 - prior_quantile): six runs know a correlation of 0.6 hardly at all, and a doubtful
        // one must not shrink the family.
        std::vector<double> r(n * n, 0.0);
        for (std::size_t a = 0; a < n; ++a) {
            r[a * n + a] = 1;
            for (std::size_t b = a + 1; b < n; ++b) {
                std::size_t k = 0;
                const double x = fitted[a] && fitted[b] ? residual_correlation(fits[a], fits[b], k) : NAN;
                if (!std::isfinite(x) || k < 4) continue;
                const double low = std::tanh(std::max(
                    0.0, std::atanh(std::min(std::fabs(x), 0.999999)) - z / std::sqrt(static_cast<double>(k) - 3)));
                r[a * n + b] = r[b * n + a] = std::copysign(low, x);
            }
        }
        // Galwey's count for each set of figures linked by a correlation, so that figures apart
        // from the rest count one each (the ratio is not additive over the blocks of a matrix).
        std::vector<std::size_t> block(n);
        for (std::size_t i = 0; i < n; ++i) block[i] = i;
        for (bool merged = true; merged;) {
            merged = false;
            for (std::size_t a = 0; a < n; ++a)
                for (std::size_t b = a + 1; b < n; ++b)
                    if (r[a * n + b] != 0 && block[a] != block[b]) {
                        block[a] = block[b] = std::min(block[a], block[b]);
                        merged = true;
                    }
        }
        for (std::size_t id = 0; id < n; ++id) {
            std::vector<std::size_t> members;
            for (std::size_t i = 0; i < n; ++i)
                if (block[i] == id) members.push_back(i);
            if (members.empty()) continue;
            const std::size_t m = members.size();
            std::vector<double> sub(m * m);
            for (std::size_t a = 0; a < m; ++a)
                for (std::size_t b = 0; b < m; ++b) sub[a * m + b] = r[members[a] * n + members[b]];
            double root = 0, sum = 0;
            for (double l : symmetric_eigenvalues(sub, m)) {
                root += std::sqrt(std::max(l, 0.0));
                sum += std::max(l, 0.0);
            }
            total += sum > 0 ? std::clamp(root * root / sum, 1.0, static_cast<double>(m)) : static_cast<double>(m);
        }
    }
    return total;
}

}  // namespace suite
