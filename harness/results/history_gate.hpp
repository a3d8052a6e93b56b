#pragma once
// `suite history check RUN.json`: a run against the recent history of the same machine, build
// and point, not against one baseline file. For each figure of each point of the run, the last
// `window` stable entries of its series (same fingerprint, context class, point and figure),
// leaving out the run's own commit, are pooled into one baseline measure: their repetitions
// concatenated, the median of the pool, its spread. `check`'s own rule (check_run and judge in
// check.hpp) then decides; there is no second decision rule here.
#include <cstdint>
#include <string>
#include <vector>

#include "harness/results/history.hpp"

namespace suite {

struct WindowBaseline {
    ResultFile file;             // the pooled baseline, one point for each point of the run with history
    std::size_t runs_pooled = 0; // distinct runs that went into it
};

// `series`: the history's series of the run's machine (others are ignored). `own_run_id`: the
// run's id when it is already in the history (0 if not), left out like its commit. A window of
// a figure whose entries are all unstable makes that point unstable (so inconclusive).
WindowBaseline window_baseline(const std::vector<Series>& series, const ResultFile& run, const RunIdentity& id, std::int64_t own_run_id,
                               std::size_t window, const std::string& label);

// The entries of one series pooled into one measure shaped like `like` (name, unit, direction).
Measure pool_entries(const std::vector<const SeriesEntry*>& entries, const Measure& like);

}  // namespace suite
