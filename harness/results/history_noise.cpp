#include "harness/results/history_noise.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <tuple>

#include "harness/common/stats.hpp"
#include "harness/results/history_gate.hpp"
#include "harness/results/history_pool.hpp"

namespace suite {

namespace {

// A series of which fewer than min_runs + 1 entries are stable (a DRAM point of 5 repetitions
// here) is gated on all its entries, as history check gates it (window_baseline).
bool flagged_series(const Series& s, std::size_t min_runs) {
    std::size_t stable = 0;
    for (const SeriesEntry& e : s.entries) stable += !e.unstable;
    return stable < min_runs + 1;
}

// The entries of a series other than the runs `skip` and `also`, the `window` nearest to the
// entry of run `skip` in the series' order (ties to the earlier one); where the series lacks
// that run, the last `window`. Only stable ones unless `any`.
std::vector<const SeriesEntry*> nearest_window(const Series& s, std::int64_t skip, std::int64_t also,
                                               std::size_t window, bool any) {
    const std::size_t n = s.entries.size();
    std::size_t from = n ? n - 1 : 0;
    for (std::size_t i = 0; i < n; ++i)
        if (s.entries[i].run_id == skip) from = i;
    std::vector<std::pair<std::size_t, std::size_t>> by_distance;  // distance, index
    for (std::size_t i = 0; i < n; ++i) {
        const SeriesEntry& e = s.entries[i];
        if (e.run_id == skip || e.run_id == also || (e.unstable && !any)) continue;
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

// The medians and runs of `entries`, as the noise model takes a window.
SeriesWindow window_of(const std::vector<const SeriesEntry*>& entries) {
    SeriesWindow out;
    for (const SeriesEntry* e : entries) {
        out.medians.push_back(e->median);
        out.runs.push_back(e->run_id);
    }
    return out;
}

// The series of one machine, build and figure, whose spreads are pooled.
struct Group {
    std::vector<const Series*> members;
    std::vector<bool> flagged;
};

// The band of member `k` of `g` leaving out runs `skip` and `also`, pooled with the others'
// windows that leave out the same runs.
RunBand pooled_band(const Group& g, std::size_t k, std::int64_t skip, std::int64_t also, std::size_t window,
                    double alpha, std::size_t min_runs, std::vector<const SeriesEntry*>* chosen = nullptr,
                    MachineNoise* noise = nullptr) {
    std::vector<SeriesWindow> windows;
    std::vector<const SeriesEntry*> own;
    for (std::size_t i = 0; i < g.members.size(); ++i) {
        const auto w = nearest_window(*g.members[i], skip, also, window, g.flagged[i]);
        windows.push_back(window_of(w));
        if (i == k) own = w;
    }
    const MachineNoise pooled = pool_spreads(windows, min_runs);
    RunBand band = fit_band(windows[k].medians, {}, alpha, min_runs, &pooled.series[k]);
    std::vector<double> se;
    for (const SeriesEntry* e : own) {
        const double x = median_standard_error(e->noise, e->samples.size());
        if (std::isfinite(x)) se.push_back(x);
    }
    if (!se.empty()) band.typical_se = median_of(se);
    if (chosen) *chosen = own;
    if (noise) *noise = pooled;
    return band;
}

}  // namespace

NoiseReport measure_noise(const std::vector<Series>& series, std::size_t window, const HistoryRule& rule, bool use_band,
                          bool confirm) {
    NoiseReport out;
    auto group_of = [](const Series& s) { return s.fingerprint + " " + s.context_class; };
    std::map<std::string, Group> groups;
    std::map<std::string, Group> machines;              // every series of a machine and build
    std::vector<std::pair<Group*, std::size_t>> place;  // each series' group and its index there
    for (const Series& s : series) {
        Group& g = groups[group_of(s) + " " + s.figure + " " + s.unit];
        place.emplace_back(&g, g.members.size());
        g.members.push_back(&s);
        g.flagged.push_back(flagged_series(s, rule.min_runs));
        machines[group_of(s)].members.push_back(&s);
        machines[group_of(s)].flagged.push_back(g.flagged.back());
    }
    // The Bonferroni family of a run gated leaving out runs `skip` and `also`, as history check
    // counts it: the figures of its machine and build that have it and a window long enough for
    // a band, as the independent tests they amount to (effective_figures).
    std::map<std::tuple<std::string, std::int64_t, std::int64_t>, double> families;
    auto family_of = [&](const Series& of, std::int64_t skip, std::int64_t also) {
        const auto id = std::make_tuple(group_of(of), skip, also);
        const auto known = families.find(id);
        if (known != families.end()) return known->second;
        const Group& m = machines[group_of(of)];
        std::map<PointKey, std::vector<SeriesWindow>> points;
        for (std::size_t i = 0; i < m.members.size(); ++i) {
            const Series& s = *m.members[i];
            const bool has = skip < 0 || std::any_of(s.entries.begin(), s.entries.end(),
                                                     [&](const SeriesEntry& e) { return e.run_id == skip; });
            const auto w = nearest_window(s, skip, also, window, m.flagged[i]);
            if (has && w.size() >= rule.min_runs) points[s.key].push_back(window_of(w));
        }
        std::vector<std::vector<SeriesWindow>> windows;
        for (auto& [key, w] : points) windows.push_back(std::move(w));
        return families[id] = effective_figures(windows, rule.min_runs);
    };
    for (const auto& [name, g] : groups) {
        MachineNoise latest;
        pooled_band(g, 0, -1, -1, window, rule.gate.alpha, rule.min_runs, nullptr, &latest);
        out.pools.push_back({g.members.front(), latest});
    }
    for (std::size_t si = 0; si < series.size(); ++si) {
        const Series& s = series[si];
        const Group& g = *place[si].first;
        const std::size_t k = place[si].second;
        const bool any = g.flagged[k];
        SeriesNoise n;
        n.series = &s;
        std::vector<const SeriesEntry*> latest;
        n.band = pooled_band(g, k, -1, -1, window, band_alpha(rule.gate.alpha, family_of(s, -1, -1)), rule.min_runs,
                             &latest);
        n.sd_spread = sd_of_logs(medians_of(latest));
        for (std::size_t i = 0; i < s.entries.size(); ++i) {
            const SeriesEntry& e = s.entries[i];
            if (e.unstable && !any) continue;
            // The confirming rerun: the next entry that could be gated.
            std::size_t j = i + 1;
            while (confirm && j < s.entries.size() && s.entries[j].unstable && !any) ++j;
            if (confirm && j >= s.entries.size()) break;
            const std::int64_t also = confirm ? s.entries[j].run_id : -1;
            const double alpha = band_alpha(rule.gate.alpha, family_of(s, e.run_id, also));
            std::vector<const SeriesEntry*> w;
            const RunBand pooled = pooled_band(g, k, e.run_id, also, window, alpha, rule.min_runs, &w);
            if (w.empty()) continue;
            // Without the band: an unusable one, so that judge_with_band is check's rule at the tolerance.
            HistoryRule r = rule;
            if (!use_band) r.auto_tolerance = false;
            const RunBand band = use_band ? pooled : RunBand{};
            // Confirmed: the entry and the next judged together, as history check --confirm does.
            const Measure run = entry_measure(e, s);
            const Verdict v =
                confirm ? judge_pair(pool_entries(w, run), run, entry_measure(s.entries[j], s), band, r).verdict
                        : judge_with_band(pool_entries(w, run), run, band, r).verdict;
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
