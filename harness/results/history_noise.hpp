#pragma once
// `suite history noise`: how much each series moves between runs, and how often the gate would
// have called an unchanged run regressed, measured on the stored runs themselves. Leave one out:
// every stable run of a series is gated, as history check gates a run, against the `window`
// stable runs of the same series nearest to it in time (itself left out), with the same band
// (its spread pooled with the other series of the figure on that machine and build, which leave
// the same run out), rule and Bonferroni family (the series of its machine and build that have
// that run). A series with too few stable runs for a band is gated on all its runs, as the gate does. A
// regression found that way is a false alarm when nothing changed between those runs; where the
// history holds real changes, they count too, so the rate is an upper bound.
#include <cstddef>
#include <cstdint>
#include <set>
#include <string>
#include <vector>

#include "harness/results/history_band.hpp"
#include "harness/results/history_pool.hpp"
#include "harness/results/history_series.hpp"

namespace suite {

struct SeriesNoise {
    const Series* series = nullptr;
    RunBand band;            // of the latest window (what the next run is held against)
    double sd_spread = NAN;  // the standard deviation of the log medians of that window: above the
                             // band's spread where a stray run is in the window (heavy tails)
    std::size_t tried = 0;   // runs (or pairs of runs, confirming) gated leaving each out
    std::size_t regressed = 0, improved = 0;
};

// The pooled model of the series of one machine, build and figure, from their latest windows.
struct PoolNoise {
    const Series* first = nullptr;  // one of them: its machine, build and figure
    MachineNoise noise;
};

struct NoiseReport {
    std::vector<SeriesNoise> series;
    std::vector<PoolNoise> pools;
    // Runs gated (per machine and build: a run counts once however many series it has) and the
    // ones with at least one figure regressed, by run id.
    std::set<std::int64_t> runs_tried, runs_alarmed;
};

// `use_band` false: check's rule on the pooled window alone, the gate before the band, to compare.
// `confirm`: each run is gated with the next stable run of its series as its confirming rerun
// (both left out of the window), and an alarm needs both to regress, as history check --confirm.
NoiseReport measure_noise(const std::vector<Series>& series, std::size_t window, const HistoryRule& rule,
                          bool use_band = true, bool confirm = false);

}  // namespace suite
