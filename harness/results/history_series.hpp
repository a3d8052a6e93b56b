#pragma once
// What `suite history` reads back out of its database for a trend: one series per machine,
// point, figure and context class (records whose context differs in a field that changes the
// result are never one series), the runs in commit order, and the steps found in it. The
// database (history.cpp) fills these; the dashboard (dashboard.cpp) and `history steps` and
// `history check` read them.
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "harness/results/result_file.hpp"

namespace suite {

// One run's value of one figure of one point.
struct SeriesEntry {
    std::string commit;  // the git revision the run was built from ("2ddd7e4d2055", "...-dirty")
    std::string branch;
    std::string date;             // the run's context date, ISO 8601 UTC
    std::int64_t run_id = 0;      // the database's id of the run
    double median = 0;            // the figure's median over the repetitions
    double noise = 0;             // relative spread of the repetitions (robust sd / median); 0: none known
    std::vector<double> samples;  // the repetitions in the figure's units, where the file had them
    // For a count (counters, callgrind): events one repetition counted (Measure::count_per_call); NAN otherwise.
    double count_per_call = NAN;
    bool unstable = false;  // flagged by the run: drawn, but not used to detect steps
};

// A change in level that persists: the series' entries from `index` on differ from the ones
// before by `change` (relative: -0.15 is 15 % lower), and p says how sure the test is.
struct Step {
    std::size_t index = 0;         // the first entry of the new level
    std::string commit;            // that entry's commit: where the step began
    double before = 0, after = 0;  // the two levels (medians of the segments)
    double change = 0;
    double p = 1;
    bool worse = false;  // in the figure's bad direction
};

struct Series {
    std::string machine;        // the fingerprint's label: "host (CPU model, N cores)"
    std::string fingerprint;    // a stable hash of the machine fields
    std::string context_class;  // the fields that split series on one machine: "THP always, -O3 -march=native"
    PointKey key;
    std::string figure, unit;  // "bandwidth", "GB/s"
    Direction direction = Direction::higher_is_better;
    std::vector<SeriesEntry> entries;  // oldest first
    std::vector<Step> steps;           // filled by the step detector
};

}  // namespace suite
