#include "harness/results/history_band.hpp"

#include <algorithm>
#include <cstdio>

#include <boost/math/distributions/students_t.hpp>

#include "harness/common/stats.hpp"

namespace suite {

namespace {

constexpr double mad_efficiency = 0.37;

std::string percent_text(double x) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.1f%%", x * 100);
    return buf;
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

RunBand fit_band(const std::vector<double>& window, const std::vector<double>& centre, double alpha,
                 std::size_t min_runs) {
    RunBand b;
    const std::vector<double>& c = centre.empty() ? window : centre;
    bool window_ok = false, centre_ok = false;
    const std::vector<double> lw = logs_of(window, window_ok), lc = logs_of(c, centre_ok);
    b.runs = window.size();
    b.centre_runs = c.size();
    if (!lc.empty() && centre_ok) b.centre = std::exp(median_of(lc));
    if (!window_ok || !centre_ok || lc.empty() || lw.size() < std::max<std::size_t>(min_runs, 2)) return b;
    const double mid = median_of(lw);
    std::vector<double> deviations;
    for (double x : lw) deviations.push_back(std::fabs(x - mid));
    b.spread = 1.4826 * median_of(deviations);
    // The MAD has 37 % of the standard deviation's efficiency for normal data, so it carries
    // about as much information as a standard deviation of 0.37 (n - 1) degrees of freedom: the
    // t quantile is taken there, not at n - 1, which would make the band too narrow for its alpha.
    const boost::math::students_t t(std::max(1.0, mad_efficiency * static_cast<double>(lw.size() - 1)));
    const double q = boost::math::quantile(boost::math::complement(t, alpha / 2));
    b.half_width = q * b.spread * std::sqrt(1 + 1 / static_cast<double>(lc.size()));
    b.low = b.centre * std::exp(-b.half_width);
    b.high = b.centre * std::exp(b.half_width);
    return b;
}

Finding judge_with_band(const Measure& base, const Measure& run, const RunBand& band, const HistoryRule& rule) {
    GateRule g = rule.gate;
    if (!band.usable()) {
        if (rule.auto_tolerance) g.tolerance = rule.fallback_tolerance;
        Finding f = judge(base, run, g);
        const std::string why = "fewer than " + std::to_string(rule.min_runs) + " runs in the window (" +
                                std::to_string(band.runs) + "): no band; check's rule at " + percent_text(g.tolerance);
        f.note = f.note.empty() ? why : why + "; " + f.note;
        return f;
    }
    if (rule.auto_tolerance) g.tolerance = rule.auto_floor;
    Measure b = base;
    b.median = band.centre;
    Finding f = judge(b, run, g);
    f.band_low = band.low;
    f.band_high = band.high;
    f.band_runs = band.runs;
    // The band's edge on the worse side, as a change of the figure: a fall for a rate, a rise
    // for a time or a count.
    const bool lower_better = base.direction == Direction::lower_is_better;
    const double edge = lower_better ? std::exp(band.half_width) - 1 : 1 - std::exp(-band.half_width);
    f.allowed = std::max(f.allowed, edge);
    const bool inside = run.median > 0 && std::fabs(std::log(run.median / band.centre)) <= band.half_width;
    if (inside && f.verdict != Verdict::unchanged) {
        f.verdict = Verdict::unchanged;
        f.note = "inside the band of the last " + std::to_string(band.runs) + " runs";
    }
    return f;
}

double band_alpha(double alpha, std::size_t family) {
    return std::min(1.0, 2 * alpha / static_cast<double>(std::max<std::size_t>(family, 1)));
}

void parse_history_tolerance(const std::string& text, HistoryRule& rule) {
    if (text == "auto") {
        rule.auto_tolerance = true;
        return;
    }
    rule.auto_tolerance = false;
    rule.gate.tolerance = parse_tolerance(text);
}

}  // namespace suite
