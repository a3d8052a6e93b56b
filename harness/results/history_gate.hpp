#pragma once
// `suite history check RUN.json`: a run against the recent history of the same machine, build
// and point, not against one baseline file. For each figure of each point of the run, the last
// `window` stable entries of its series (same fingerprint, context class, point and figure),
// leaving out the run's own commit, are pooled into one baseline measure: their repetitions
// concatenated, the median of the pool, its spread. `check`'s own rule (check_run and judge in
// check.hpp) decides, with one more condition where the series has runs enough: the run's median
// must also leave the band of the runs' medians (history_band.hpp), which carries how runs differ
// from one another, something the repetitions of one run cannot show.
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "harness/results/history.hpp"
#include "harness/results/history_band.hpp"

namespace suite {

struct WindowBaseline {
    ResultFile file;              // the pooled baseline, one point for each point of the run with history
    std::size_t runs_pooled = 0;  // distinct runs that went into it
    // For each point and figure ("bandwidth GB/s") pooled: the medians of the window's runs (for
    // the spread) and of the runs pooled (for the centre: the window's, or the base commit's).
    // `runs` and `se`: the window's run ids (for pooling) and the standard errors of their
    // medians from their own repetitions (median_standard_error; NAN where unknown).
    struct Medians {
        std::vector<double> window, centre;
        std::vector<std::int64_t> runs;
        std::vector<double> se;
    };
    std::map<std::pair<PointKey, std::string>, Medians> medians;
};

// `series`: the history's series of the run's machine (others are ignored). `own_run_id`: the
// run's id when it is already in the history (0 if not), left out like its commit. A window of
// a figure with fewer than `min_runs` stable entries takes its latest entries, flagged or not
// (the band then carries their spread); one whose entries are all unstable and fewer than
// `min_runs` makes that point unstable (so inconclusive).
// `base_commit` "": the window's runs are pooled; otherwise the stable runs of that commit (a
// prefix of at least 7 hex digits either way) are, and a point without any is left out.
WindowBaseline window_baseline(const std::vector<Series>& series, const ResultFile& run, const RunIdentity& id,
                               std::int64_t own_run_id, std::size_t window, const std::string& label,
                               const std::string& base_commit = "", std::size_t min_runs = HistoryRule{}.min_runs);

// The entries of one series pooled into one measure shaped like `like` (name, unit, direction).
Measure pool_entries(const std::vector<const SeriesEntry*>& entries, const Measure& like);

// Whether a stored commit and a given one name the same commit: equal, or one a prefix of the
// other of at least 7 characters (the history may hold "2ddd7e4d2055" and CI pass all 40).
bool same_commit(const std::string& stored, const std::string& given);

// `history check`: check_run against the pooled baseline, then each figure judged again with its
// band (judge_with_band): one band a point and figure, each at alpha · 2 / F, F the figures
// with a band as the independent tests they amount to (Bonferroni over the run's figures,
// effective_figures in history_pool.hpp). rule_text says how; the notes name the figures gated
// without a band.
// `rerun` (--confirm): a rerun of the same build; each figure is then judged on both runs
// together (judge_pair).
CheckReport gate_with_bands(const WindowBaseline& base, const ResultFile& run, const HistoryRule& rule,
                            const ResultFile* rerun = nullptr);

// --confirm's note on the report: which rerun, and how the two were judged.
void note_confirmation(CheckReport& rep, const std::string& rerun_path);

}  // namespace suite
