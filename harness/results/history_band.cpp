#include "harness/results/history_band.hpp"

#include <algorithm>
#include <cstdio>

#include <boost/math/distributions/students_t.hpp>

#include "harness/common/stats.hpp"
#include "harness/common/units.hpp"
#include "harness/results/history_pool.hpp"
#include "harness/results/history_scale.hpp"

namespace suite {

namespace {

std::string percent_text(double x) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.1f%%", x * 100);
    return buf;
}

// "+12.5%" or "-3%": a ratio's change, signed.
std::string signed_change(double ratio) {
    const double c = (ratio - 1) * 100;
    return (c >= 0 ? "+" : "") + format_significant(c, 3) + "%";
}

std::vector<double> logs_of(const std::vector<double>& v, bool& all_positive) {
    std::vector<double> out;
    all_positive = true;
    for (double x : v) {
        if (!(x > 0) || !std::isfinite(x))
            all_positive = false;
        else
            out.push_back(std::log(x));
    }
    return out;
}

}  // namespace

double RunBand::widened(double se) const {
    const double typical = std::isfinite(typical_se) ? typical_se : 0;
    if (!usable() || !std::isfinite(se) || se <= typical) return half_width;
    return half_for(se * se - typical * typical);
}

double RunBand::runs_variance() const {
    const double m = static_cast<double>(std::max<std::size_t>(centre_runs, 1));
    return spread * spread * (run_share + 1 / m);
}

double RunBand::half_for(double extra) const {
    const double c = std::sqrt(std::max(0.0, runs_variance() + extra));
    const double core = quantile * c;
    if (jumps.empty() || !(jump_rate > 0) || !(c > 0) || !std::isfinite(core) || !(alpha > 0)) return core;
    const std::vector<double>& j = jumps;  // sorted, at most 32 (find_jumps)
    const boost::math::students_t t(std::max(0.5, df));
    auto tail = [&](double z) { return boost::math::cdf(boost::math::complement(t, z)); };
    const double p = std::min(jump_rate, 1.0), k = static_cast<double>(j.size());
    const double cj = std::sqrt(c * c + jump_spread * jump_spread);
    auto outside = [&](double h) {
        double jumped = 0;
        for (double d : j) jumped += tail((h - d) / cj) + tail((h + d) / cj);
        return (1 - p) * 2 * tail(h / c) + p / k * jumped;
    };
    // outside() falls with h; at the largest jump plus quantile * c_j each of its terms is at most
    // its share of alpha.
    double lo = core, hi = j.back() + quantile * cj;
    if (outside(lo) <= alpha) return core;
    for (int i = 0; i < 50 && hi - lo > 1e-9 * hi; ++i) {
        const double mid = (lo + hi) / 2;
        (outside(mid) > alpha ? lo : hi) = mid;
    }
    return hi;
}

RunBand RunBand::for_pair() const {
    RunBand b = *this;
    b.run_share = (1 + rerun_correlation) / 2;
    if (!usable()) return b;
    b.half_width = b.half_for(0);
    b.low = centre * std::exp(-b.half_width);
    b.high = centre * std::exp(b.half_width);
    return b;
}

double median_standard_error(double noise, std::size_t n) {
    if (n < 2 || !(noise > 0)) return NAN;
    return std::sqrt(std::acos(-1.0) / 2) * noise / std::sqrt(static_cast<double>(n));
}

RunBand fit_band(const std::vector<double>& window, const std::vector<double>& centre, double alpha,
                 std::size_t min_runs, const PooledSpread* pooled) {
    RunBand b;
    const std::vector<double>& c = centre.empty() ? window : centre;
    bool window_ok = false, centre_ok = false;
    const std::vector<double> lw = logs_of(window, window_ok), lc = logs_of(c, centre_ok);
    b.runs = window.size();
    b.centre_runs = c.size();
    if (!lc.empty() && centre_ok) b.centre = std::exp(median_of(lc));
    if (!window_ok || !centre_ok || lc.empty() || lw.size() < std::max<std::size_t>(min_runs, 2)) return b;
    const ScaleEstimate own = qn_scale(lw);
    b.own_spread = b.spread = own.sigma;
    b.df = own.df;
    if (pooled && std::isfinite(pooled->sigma) && pooled->df > 0) {
        b.spread = pooled->sigma;
        b.df = pooled->df;
    }
    if (pooled) {
        b.jumps = pooled->jumps;
        b.jump_rate = pooled->jump_rate;
        b.jump_spread = pooled->jump_spread;
    }
    b.alpha = alpha;
    const boost::math::students_t t(std::max(0.5, b.df));
    b.quantile = boost::math::quantile(boost::math::complement(t, alpha / 2));
    b.half_width = b.half_for(0);  // centre_runs = lc.size() here
    b.low = b.centre * std::exp(-b.half_width);
    b.high = b.centre * std::exp(b.half_width);
    return b;
}

std::string no_band_reason(const RunBand& band, std::size_t min_runs) {
    if (band.runs < min_runs)
        return "fewer than " + std::to_string(min_runs) + " runs in the window (" + std::to_string(band.runs) +
               "): " + std::to_string(min_runs - band.runs) + " more run(s) needed for a band";
    return "a median in the window is not a positive number: no band";
}

Finding judge_with_band(const Measure& base, const Measure& run, const RunBand& band, const HistoryRule& rule) {
    GateRule g = rule.gate;
    if (!band.usable()) {
        if (rule.auto_tolerance) g.tolerance = rule.fallback_tolerance;
        Finding f = judge(base, run, g);
        const std::string why = no_band_reason(band, rule.min_runs) + "; check's rule at " + percent_text(g.tolerance);
        f.note = f.note.empty() ? why : why + "; " + f.note;
        return f;
    }
    if (rule.auto_tolerance) g.tolerance = rule.auto_floor;
    Measure b = base;
    b.median = band.centre;
    Finding f = judge(b, run, g);
    const double noise = run.samples.size() >= 2 ? robust_relative_spread(run.samples) : NAN;
    const double se = median_standard_error(noise, run.samples.size());
    const double half = band.widened(se);
    f.band_low = band.centre * std::exp(-half);
    f.band_high = band.centre * std::exp(half);
    f.band_runs = band.runs;
    // The band's edge on the worse side, as a change of the figure: a fall for a rate, a rise
    // for a time or a count.
    const bool lower_better = base.direction == Direction::lower_is_better;
    const double edge = lower_better ? std::exp(half) - 1 : 1 - std::exp(-half);
    f.allowed = std::max(f.allowed, edge);
    const double distance = run.median > 0 ? std::fabs(std::log(run.median / band.centre)) : INFINITY;
    // A count of a few events a repetition: judge's own verdict (not gated by ratio) stands.
    if (f.verdict == Verdict::unchanged && !f.note.empty()) return f;
    // The band decides, not the Mann-Whitney test of the repetitions (its p stays in the
    // finding): that test takes the window's repetitions for one sample, which they are not,
    // and one stray repetition of a busy run in the pool hides a 2x change from it.
    const double change = run.median / band.centre - 1;
    const double worse_change = lower_better ? change : -change;
    const Verdict was = f.verdict;
    f.note.clear();
    if (distance <= band.half_width || std::fabs(worse_change) <= g.tolerance) {
        f.verdict = Verdict::unchanged;
        if (was != Verdict::unchanged) f.note = "inside the band of the last " + std::to_string(band.runs) + " runs";
    } else if (distance <= half) {
        // Outside the runs' band, inside what this run's own repetitions leave open: the
        // repetitions that would tell, were they as spread as these (se^2 = pi/2 noise^2 / n).
        // The variance beyond the band's own that puts its edge at this distance (with jumps, by
        // bisection: half_for rises with it).
        const double typical = std::isfinite(band.typical_se) ? band.typical_se : 0;
        double extra = std::pow(distance / band.quantile, 2) - band.runs_variance();
        if (!band.jumps.empty()) {
            double lo = 0, hi = distance * distance;
            for (int i = 0; i < 40 && hi - lo > 1e-9 * hi; ++i) {
                const double mid = (lo + hi) / 2;
                (band.half_for(mid) < distance ? lo : hi) = mid;
            }
            extra = lo;
        }
        const double room = extra + typical * typical;
        const double reps = std::ceil(std::acos(-1.0) / 2 * noise * noise / room);
        const bool below = run.median < band.centre;
        f.verdict = Verdict::inconclusive;
        f.note = "outside the runs' band but inside it widened by this run's own repetitions (spread " +
                 percent_text(noise) + " over " + std::to_string(run.samples.size()) + "): it would need a median " +
                 (below ? "below " : "above ") + format_significant(below ? f.band_low : f.band_high, 4) + " " +
                 run.unit + ", or about " + format_significant(reps, 3) + " repetitions as spread as these";
    } else {
        f.verdict = worse_change > 0 ? Verdict::regressed : Verdict::improved;
    }
    return f;
}

Finding judge_pair(const Measure& base, const Measure& run, const Measure& rerun, const RunBand& band,
                   const HistoryRule& rule) {
    if (!band.usable() || !(run.median > 0) || !(rerun.median > 0)) {
        Finding f = judge_with_band(base, run, band, rule);
        const Finding g = judge_with_band(base, rerun, band, rule);
        if ((f.verdict == Verdict::regressed || f.verdict == Verdict::improved) && g.verdict != f.verdict) {
            f.note = std::string(f.verdict == Verdict::regressed ? "regressed" : "improved") +
                     " here but not in the rerun (" + signed_change(g.run / g.baseline) + " there)";
            f.verdict = Verdict::inconclusive;
        }
        return f;
    }
    // The pair's median, and both runs' repetitions each moved onto it: their spread is the runs'
    // own noise, not the distance between the two, which the band's spread already carries.
    Measure pair = run;
    pair.median = std::sqrt(run.median * rerun.median);
    pair.samples.clear();
    for (const Measure* m : {&run, &rerun})
        for (double x : m->samples) pair.samples.push_back(x * pair.median / m->median);
    Finding f = judge_with_band(base, pair, band.for_pair(), rule);
    if (f.verdict != Verdict::regressed && f.verdict != Verdict::improved) return f;
    // Each run on its own must have moved the same way by more than the minimum effect.
    const bool lower_better = base.direction == Direction::lower_is_better;
    const double effect = rule.auto_tolerance ? rule.auto_floor : rule.gate.tolerance;
    auto worse = [&](double median) {
        const double change = median / band.centre - 1;
        return lower_better ? change : -change;
    };
    const double w1 = worse(run.median), w2 = worse(rerun.median);
    const bool agree = f.verdict == Verdict::regressed ? w1 > effect && w2 > effect : w1 < -effect && w2 < -effect;
    if (agree) return f;
    f.note = "the mean of the run and its rerun left the band, but not both runs moved that way by more than " +
             percent_text(effect) + " (run " + signed_change(run.median / band.centre) + ", rerun " +
             signed_change(rerun.median / band.centre) + ")";
    f.verdict = Verdict::inconclusive;
    return f;
}

double band_alpha(double alpha, double family) { return std::min(1.0, 2 * alpha / std::max(family, 1.0)); }

void parse_history_tolerance(const std::string& text, HistoryRule& rule) {
    if (text == "auto") {
        rule.auto_tolerance = true;
        return;
    }
    rule.auto_tolerance = false;
    rule.gate.tolerance = parse_tolerance(text);
}

}  // namespace suite
