#pragma once
// Steps in a series: a change of level that persists from one commit on. Binary segmentation:
// every split of a segment between two commits, with at least `min_side` entries each side, is
// tested (the Mann–Whitney test of the entries' medians before against after, two-sided); a
// split is a step when its p-value, times the number of splits tried (Bonferroni), is below
// `alpha` and the levels (the medians of the two sides) differ by at least `min_effect`. The most
// significant split is taken, and each side is searched again. Where no single split is a step,
// a bump is looked for (a stretch of commits that differs from both sides taken together: a
// regression later fixed), tested the same way against every pair of boundaries scanned. Only stable entries are used
// (an entry the run flagged unstable is drawn, never tested). Deterministic: ties go to the
// larger change, then to the earlier split.
#include <cstddef>
#include <vector>

#include "harness/results/history_series.hpp"

namespace suite {

struct StepRule {
    double min_effect = 0.05;  // relative change between the levels, below which nothing is a step
    double alpha = 0.01;       // after the Bonferroni correction
    // Entries each side of a split. Few can reach alpha: 3 against 27, all apart, gives p = 5e-4
    // before the correction; a step needs about 5 runs on each side to be found.
    std::size_t min_side = 3;
};

// The steps of `series`, oldest first; Step::index is an index into series.entries.
std::vector<Step> detect_steps(const Series& series, const StepRule& options = {});

}  // namespace suite
