#include "harness/results/history_noise.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>

#include "harness/common/stats.hpp"
#include "harness/results/history_gate.hpp"

namespace suite {

namespace {

// The stable entries of a series other than `skip` (and `also`), the `window` nearest to `skip`
// in the series' order (ties to the earlier one); `skip` = entries.size(): the last `window`.
std::vector<const SeriesEntry*> nearest_window(const Series& s, std::size_t skip, std::size_t window,
                                               std::size_t also = SIZE_MAX) {
    std::vector<std::pair<std::size_t, std::size_t>> by_distance;  // distance, index
    const std::size_t n = s.entries.size();
    for (std::size_t i = 0; i < n; ++i) {
        if (i == skip || i == also || s.entries[i].unstable) continue;
        const std::size_t from = skip == n ? n - 1 : skip;
        by_distance.emplace_back(i > from ? i - from : from - i, i);
    }
    std::sort(by_distance.begin(), by_distance.end());
    if (by_distance.size() > window) by_distance.resize(window);
    std::vector<std::size_t> chosen;
    for (const auto& d : by_distance) chosen.push_back(d.second);
    std::sort(chosen.begin(), chosen.end());
    std::vector<const SeriesEntry*> out;
    for (std::size_t i : chosen) out.push_back(&s.entries[i]);
    return out;
}

std::vector<double> medians_of(const std::vector<const SeriesEntry*>& entries) {
    std::vector<double> out;
    for (const SeriesEntry* e : entries) out.push_back(e->median);
    return out;
}

Measure entry_measure(const SeriesEntry& e, const Series& s) {
    Measure m;
    m.name = s.figure;
    m.unit = s.unit;
    m.direction = s.direction;
    m.median = m.best = e.median;
    m.noise = e.noise;
    m.samples = e.samples;
    m.count_per_call = e.count_per_call;
    return m;
}

double sd_of_logs(const std::vector<double>& medians) {
    std::vector<double> logs;
    for (double m : medians)
        if (m > 0) logs.push_back(std::log(m));
    if (logs.size() < 2) return NAN;
    double mean = 0, ss = 0;
    for (double l : logs) mean += l;
    mean /= static_cast<double>(logs.size());
    for (double l : logs) ss += (l - mean) * (l - mean);
    return std::sqrt(ss / static_cast<double>(logs.size() - 1));
}

}  // namespace

NoiseReport measure_noise(const std::vector<Series>& series, std::size_t window, const HistoryRule& rule, bool use_band,
                          bool confirm) {
    NoiseReport out;
    // The Bonferroni family of a run: the series of its machine and build that have it.
    std::map<std::pair<std::string, std::int64_t>, std::size_t> family;
    auto group_of = [](const Series& s) { return s.fingerprint + " " + s.context_class; };
    for (const Series& s : series)
        for (const SeriesEntry& e : s.entries) ++family[{group_of(s), e.run_id}];
    for (const Series& s : series) {
        SeriesNoise n;
        n.series = &s;
        const std::vector<const SeriesEntry*> latest = nearest_window(s, s.entries.size(), window);
        const std::size_t latest_family = s.entries.empty() ? 1 : family[{group_of(s), s.entries.back().run_id}];
        n.band = fit_band(medians_of(latest), {}, band_alpha(rule.gate.alpha, latest_family), rule.min_runs);
        n.sd_spread = sd_of_logs(medians_of(latest));
        for (std::size_t i = 0; i < s.entries.size(); ++i) {
            const SeriesEntry& e = s.entries[i];
            if (e.unstable) continue;
            // The confirming rerun: the next stable entry.
            std::size_t j = i + 1;
            while (confirm && j < s.entries.size() && s.entries[j].unstable) ++j;
            if (confirm && j >= s.entries.size()) break;
            const std::vector<const SeriesEntry*> w = nearest_window(s, i, window, confirm ? j : SIZE_MAX);
            if (w.empty()) continue;
            const double alpha = band_alpha(rule.gate.alpha, family[{group_of(s), e.run_id}]);
            // Without the band: an unusable one, so that judge_with_band is check's rule at the tolerance.
            HistoryRule r = rule;
            if (!use_band) r.auto_tolerance = false;
            const RunBand band = use_band ? fit_band(medians_of(w), {}, alpha, rule.min_runs) : RunBand{};
            auto verdict_of = [&](const SeriesEntry& x) {
                const Measure run = entry_measure(x, s);
                return judge_with_band(pool_entries(w, run), run, band, r).verdict;
            };
            Verdict v = verdict_of(e);
            if (confirm && v != verdict_of(s.entries[j])) v = Verdict::inconclusive;
            ++n.tried;
            out.runs_tried.insert(e.run_id);
            if (v == Verdict::regressed) {
                ++n.regressed;
                out.runs_alarmed.insert(e.run_id);
            } else if (v == Verdict::improved) {
                ++n.improved;
            }
        }
        out.series.push_back(std::move(n));
    }
    return out;
}

}  // namespace suite
