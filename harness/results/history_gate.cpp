#include "harness/results/history_gate.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <tuple>

#include "harness/common/stats.hpp"

namespace suite {

Measure pool_entries(const std::vector<const SeriesEntry*>& entries, const Measure& like) {
    Measure m;
    m.name = like.name;
    m.unit = like.unit;
    m.direction = like.direction;
    std::vector<double> medians, noises, counts;
    for (const SeriesEntry* e : entries) {
        m.samples.insert(m.samples.end(), e->samples.begin(), e->samples.end());
        medians.push_back(e->median);
        noises.push_back(e->noise);
        if (std::isfinite(e->count_per_call)) counts.push_back(e->count_per_call);
    }
    if (medians.empty()) return m;
    m.median = m.samples.empty() ? median_of(medians) : median_of(m.samples);
    m.best = m.median;
    // The pool's spread holds both each run's own noise and how runs differ from one another;
    // without repetitions, the larger of the runs' typical noise and the spread of their medians.
    m.noise = m.samples.size() >= 2 ? robust_relative_spread(m.samples) : std::max(median_of(noises), robust_relative_spread(medians));
    if (!counts.empty()) m.count_per_call = median_of(counts);
    return m;
}

WindowBaseline window_baseline(const std::vector<Series>& series, const ResultFile& run, const RunIdentity& id, std::int64_t own_run_id,
                               std::size_t window, const std::string& label) {
    using SeriesId = std::tuple<std::string, PointKey, std::string, std::string>;  // class, point, figure, unit
    std::map<SeriesId, const Series*> by_id;
    for (const Series& s : series)
        if (s.fingerprint == id.fingerprint) by_id[{s.context_class, s.key, s.figure, s.unit}] = &s;
    WindowBaseline out;
    out.file.path = label;
    out.file.schema_version = run.schema_version;
    // The window was chosen to match the run's machine and build, so the run's context describes it.
    out.file.context = run.context;
    std::set<std::int64_t> pooled_runs;
    for (const LoadedPoint& p : run.points) {
        LoadedPoint b;
        b.key = p.key;
        b.hugepages = p.hugepages;
        bool all_unstable = false;
        for (const Measure& m : p.measures) {
            auto it = by_id.find({series_class(id.context_class, p.hugepages), p.key, m.name, m.unit});
            if (it == by_id.end()) continue;
            std::vector<const SeriesEntry*> stable, unstable;
            const auto& entries = it->second->entries;
            for (auto e = entries.rbegin(); e != entries.rend() && stable.size() < window; ++e) {
                const bool own = (id.commit != "unknown" && e->commit == id.commit) || (own_run_id != 0 && e->run_id == own_run_id);
                if (!own) (e->unstable ? unstable : stable).push_back(&*e);
            }
            if (stable.empty() && unstable.empty()) continue;
            if (stable.empty()) {
                // Only unstable runs to compare with: pooled all the same, and flagged, so check calls it inconclusive.
                if (unstable.size() > window) unstable.resize(window);
                stable = unstable;
                all_unstable = true;
            }
            std::reverse(stable.begin(), stable.end());  // oldest first, as the series
            for (const SeriesEntry* e : stable) pooled_runs.insert(e->run_id);
            b.measures.push_back(pool_entries(stable, m));
        }
        if (b.measures.empty()) continue;
        if (all_unstable) {
            b.unstable = true;
            b.unstable_why = "every run of the history's window was flagged unstable";
        }
        out.file.points.push_back(std::move(b));
    }
    out.runs_pooled = pooled_runs.size();
    return out;
}

}  // namespace suite
