#include "harness/results/history_gate.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <tuple>

#include "harness/common/stats.hpp"
#include "harness/common/units.hpp"
#include "harness/results/history_pool.hpp"

namespace suite {

namespace {

// The median of the known standard errors of the window's medians; NAN where none is known.
double typical_standard_error(const std::vector<double>& se) {
    std::vector<double> known;
    for (double x : se)
        if (std::isfinite(x)) known.push_back(x);
    return known.empty() ? NAN : median_of(known);
}

// "bandwidth GB/s: 4 series' spreads pooled (the machine's 3.1 %, worth 8.2 degrees of freedom;
// their runs' noise correlates 0.45: as 2.1 independent series)".
std::string pooled_note(const std::string& figure, const MachineNoise& n) {
    return figure + ": the spreads of " + std::to_string(n.series.size()) + " series pooled (the machine's " +
           format_significant(n.prior * 100, 2) + "%, worth " + format_significant(n.prior_df, 3) +
           " degrees of freedom; their runs' noise correlates " +
           (std::isfinite(n.shared) ? format_significant(n.shared, 2) : std::string("-")) + ": as " +
           format_significant(n.effective_series, 2) + " independent series)";
}

// "bandwidth GB/s: 2 of the windows' 24 runs jumped (up to 31%, beyond 4 of their series'
// spreads): the machine changed state, and every band of the figure takes such a jump in".
std::string jumps_note(const std::string& figure, const MachineNoise& n) {
    return figure + ": " + std::to_string(n.jumps.size()) + " of the windows' " + std::to_string(n.jump_runs) +
           " runs jumped (up to " + format_significant((std::exp(n.largest_jump()) - 1) * 100, 2) + "%, beyond " +
           format_significant(jump_sigmas, 2) +
           " of their series' spreads): the machine changed state, and every band of the figure takes such a jump in";
}

}  // namespace

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
    m.noise = m.samples.size() >= 2 ? robust_relative_spread(m.samples)
                                    : std::max(median_of(noises), robust_relative_spread(medians));
    if (!counts.empty()) m.count_per_call = median_of(counts);
    return m;
}

bool same_commit(const std::string& stored, const std::string& given) {
    if (stored == given) return true;
    const std::size_t n = std::min(stored.size(), given.size());
    return n >= 7 && stored.compare(0, n, given, 0, n) == 0;
}

WindowBaseline window_baseline(const std::vector<Series>& series, const ResultFile& run, const RunIdentity& id,
                               std::int64_t own_run_id, std::size_t window, const std::string& label,
                               const std::string& base_commit, std::size_t min_runs) {
    using SeriesId = std::tuple<std::string, PointKey, std::string, std::string>;  // class, point, figure, unit
    std::map<SeriesId, const Series*> by_id;
    for (const Series& s : series)
        if (s.fingerprint == id.fingerprint) by_id[{s.context_class, s.key, s.figure, s.unit}] = &s;
    WindowBaseline out;
    out.file.path = label;
    out.file.schema_version = run.schema_version;
    // The window was chosen to match the run's machine and build, so the run's context describes
    // it; and its processes: in an MPI run each point is one rank's (or the aggregate's) series.
    out.file.context = run.context;
    out.file.mpi = run.mpi;
    std::set<std::int64_t> pooled_runs;
    for (const LoadedPoint& p : run.points) {
        LoadedPoint b;
        b.key = p.key;
        b.hugepages = p.hugepages;
        bool all_unstable = false;
        for (const Measure& m : p.measures) {
            auto it = by_id.find({series_class(id.context_class, p.hugepages), p.key, m.name, m.unit});
            if (it == by_id.end()) continue;
            std::vector<const SeriesEntry*> stable, unstable, base;
            const auto& entries = it->second->entries;
            for (auto e = entries.rbegin(); e != entries.rend(); ++e) {
                const bool own =
                    (id.commit != "unknown" && e->commit == id.commit) || (own_run_id != 0 && e->run_id == own_run_id);
                if (own) continue;
                if (!base_commit.empty() && !e->unstable && same_commit(e->commit, base_commit)) base.push_back(&*e);
                if (stable.size() < window) (e->unstable ? unstable : stable).push_back(&*e);
            }
            // A point whose runs are mostly flagged unstable (a DRAM point of 5 repetitions here)
            // is gated all the same: the latest runs, flagged or not, make its window, and their
            // spread makes its band as wide as it has to be.
            if (stable.size() < min_runs) {
                std::vector<const SeriesEntry*> any;
                for (auto e = entries.rbegin(); e != entries.rend() && any.size() < window; ++e)
                    if (!((id.commit != "unknown" && e->commit == id.commit) ||
                          (own_run_id != 0 && e->run_id == own_run_id)))
                        any.push_back(&*e);
                if (any.size() > stable.size()) {
                    stable = std::move(any);
                    unstable.clear();
                }
            }
            WindowBaseline::Medians med;
            for (const SeriesEntry* e : stable) {
                med.window.push_back(e->median);
                med.runs.push_back(e->run_id);
                med.se.push_back(median_standard_error(e->noise, e->samples.size()));
            }
            // Flagged runs only, and too few of them for a band: check calls the point inconclusive.
            const bool flagged_only =
                !stable.empty() && stable.size() < min_runs &&
                std::all_of(stable.begin(), stable.end(), [](const SeriesEntry* e) { return e->unstable; });
            all_unstable = all_unstable || (base_commit.empty() && flagged_only);
            std::vector<const SeriesEntry*>& pooled = base_commit.empty() ? stable : base;
            if (!base_commit.empty() && base.empty()) continue;  // the base commit never ran this point
            if (pooled.empty() && unstable.empty()) continue;
            if (pooled.empty()) {
                // Only unstable runs to compare with: pooled all the same, and flagged, so check calls it inconclusive.
                if (unstable.size() > window) unstable.resize(window);
                pooled = unstable;
                all_unstable = true;
            }
            std::reverse(pooled.begin(), pooled.end());  // oldest first, as the series
            for (const SeriesEntry* e : pooled) {
                pooled_runs.insert(e->run_id);
                med.centre.push_back(e->median);
            }
            b.measures.push_back(pool_entries(pooled, m));
            out.medians[{p.key, m.name + " " + m.unit}] = std::move(med);
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

namespace {

// A counter of CPU time (task-clock, cpu-clock) is the repetitions' time read a second way: it
// has no repetitions of its own in the file, so it takes its point's, each repetition's time
// relative to their median (from the timed figure's samples), and its band is widened by the
// same repetitions as the rate's. Without that a run whose bandwidth was inconclusive (its
// repetitions spread) could regress on its task-clock, the same time, unwidened.
Measure with_time_samples(const Measure& m, const LoadedPoint& p) {
    const bool clock = m.name == "counter task-clock" || m.name == "counter cpu-clock";
    if (!clock || !m.samples.empty() || !(m.median > 0)) return m;
    for (const Measure& timed : p.measures) {
        if (timed.samples.size() < 2 || !(timed.median > 0)) continue;
        Measure out = m;
        for (double x : timed.samples) {
            if (!(x > 0)) return m;
            const double time = timed.direction == Direction::higher_is_better ? timed.median / x : x / timed.median;
            out.samples.push_back(m.median * time);
        }
        return out;
    }
    return m;
}

}  // namespace

CheckReport gate_with_bands(const WindowBaseline& base, const ResultFile& run, const HistoryRule& rule,
                            const ResultFile* rerun) {
    CheckReport rep = check_run(base.file, run, rule.gate, true);
    std::map<PointKey, const LoadedPoint*> in_base, in_run, in_rerun;
    for (const auto& p : base.file.points) in_base[matching_key(p.key)] = &p;
    for (const auto& p : run.points) in_run[matching_key(p.key)] = &p;
    if (rerun)
        for (const auto& p : rerun->points) in_rerun[matching_key(p.key)] = &p;
    auto measure_of = [](const LoadedPoint* p, const std::string& figure) -> const Measure* {
        for (const auto& m : p->measures)
            if (m.name + " " + m.unit == figure) return &m;
        return nullptr;
    };
    // The family of the Bonferroni correction: every figure judged that has runs enough for a
    // band, counted as the independent tests they amount to (effective_figures).
    std::size_t family = 0;
    std::map<PointKey, std::vector<SeriesWindow>> family_points;
    for (const auto& f : rep.findings) {
        auto it = base.medians.find({f.key, f.figure});
        if (it == base.medians.end() || !fit_band(it->second.window, it->second.centre, 0.5, rule.min_runs).usable())
            continue;
        ++family;
        family_points[f.key].push_back({it->second.window, it->second.runs});
    }
    std::vector<std::vector<SeriesWindow>> points;
    for (auto& [key, windows] : family_points) points.push_back(std::move(windows));
    const double effective = effective_figures(points, rule.min_runs);
    const double alpha = band_alpha(rule.gate.alpha, family ? effective : 0);
    // The series of one figure share the machine's noise: their spreads are pooled (history_pool.hpp).
    std::map<std::string, std::vector<std::pair<PointKey, SeriesWindow>>> by_figure;
    for (const auto& [id, med] : base.medians) by_figure[id.second].push_back({id.first, {med.window, med.runs}});
    std::map<std::pair<PointKey, std::string>, PooledSpread> pooled;
    for (const auto& [figure, members] : by_figure) {
        std::vector<SeriesWindow> windows;
        for (const auto& m : members) windows.push_back(m.second);
        const MachineNoise noise = pool_spreads(windows, rule.min_runs);
        for (std::size_t i = 0; i < members.size(); ++i) pooled[{members[i].first, figure}] = noise.series[i];
        if (noise.prior_df > 0) rep.notes.push_back(pooled_note(figure, noise));
        if (!noise.jumps.empty()) rep.notes.push_back(jumps_note(figure, noise));
    }
    std::size_t without_band = 0;
    for (Finding& f : rep.findings) {
        const auto b = in_base.find(matching_key(f.key)), r = in_run.find(matching_key(f.key));
        const auto med = base.medians.find({f.key, f.figure});
        if (b == in_base.end() || r == in_run.end() || med == base.medians.end()) continue;  // verification failures
        const Measure *bm = measure_of(b->second, f.figure), *rm = measure_of(r->second, f.figure);
        if (!bm || !rm) continue;
        RunBand band =
            fit_band(med->second.window, med->second.centre, alpha, rule.min_runs, &pooled[{f.key, f.figure}]);
        band.typical_se = typical_standard_error(med->second.se);
        const auto rr = in_rerun.find(matching_key(f.key));
        const Measure* rrm = rr == in_rerun.end() ? nullptr : measure_of(rr->second, f.figure);
        const Measure run_m = with_time_samples(*rm, *r->second);
        Finding g = rrm ? judge_pair(*bm, run_m, with_time_samples(*rrm, *rr->second), band, rule)
                        : judge_with_band(*bm, run_m, band, rule);
        if (rerun && !rrm && (g.verdict == Verdict::regressed || g.verdict == Verdict::improved)) {
            g.verdict = Verdict::inconclusive;
            g.note = "the rerun " + rerun->path + " lacks this figure: nothing confirms the change";
        }
        g.key = f.key;
        g.host = f.host;
        without_band += !band.usable() && band.runs < rule.min_runs;
        // Without a band, check_run's verdict on an unstable point stands: inconclusive whatever
        // the change. With one, the band widened by the run's own repetitions has judged it.
        const bool timed = bm->name.rfind("callgrind", 0) != 0;
        const bool rerun_unstable = rr != in_rerun.end() && rr->second->unstable;
        if (timed && !band.usable() && (b->second->unstable || r->second->unstable || rerun_unstable)) {
            g.verdict = Verdict::inconclusive;
            g.note = f.note;
        }
        f = std::move(g);
    }
    auto percent = [](double x) { return format_significant(x * 100, 3) + "%"; };
    const std::string effect = rule.auto_tolerance
                                   ? "the band's edge (--tolerance=auto, at least " + percent(rule.auto_floor) + ")"
                                   : percent(rule.gate.tolerance);
    rep.rule_text =
        "a change counts when the run's median leaves the band of the runs' medians (a t prediction interval, "
        "the spread pooled with the machine's, widened by the machine's jumps in the window and by the run's own "
        "repetitions, at " +
        format_significant(alpha, 3) + " a figure: alpha " + format_significant(rule.gate.alpha, 3) +
        (rerun ? "; with a rerun, the two runs' mean against the band for a mean of two (their noise taken to "
                 "correlate " +
                     format_significant(rerun_correlation, 2) + "), and each run moved that way"
               : "") +
        " over " + std::to_string(family) + " figures, " + format_significant(effective, 3) +
        " as independent tests since their runs' noise correlates) and is beyond " + effect +
        "; without a band, when the repetitions tell it from the pool's at p < " +
        format_significant(rule.gate.alpha, 3);
    if (without_band) {
        std::size_t fewest = SIZE_MAX;
        for (const auto& [id, med] : base.medians)
            if (med.window.size() < rule.min_runs) fewest = std::min(fewest, med.window.size());
        rep.notes.push_back(std::to_string(without_band) + " figure(s) have fewer than " +
                            std::to_string(rule.min_runs) + " runs in the window (the fewest " +
                            std::to_string(fewest) + ": " +
                            std::to_string(rule.min_runs - std::min(fewest, rule.min_runs)) +
                            " more run(s) needed): no band; check's rule at " +
                            percent(rule.auto_tolerance ? rule.fallback_tolerance : rule.gate.tolerance));
    }
    return rep;
}

void note_confirmation(CheckReport& rep, const std::string& rerun_path) {
    rep.notes.push_back("confirmed by " + rerun_path +
                        ": judged on the mean of the two runs, and a change counts only where both runs show it");
}

}  // namespace suite
