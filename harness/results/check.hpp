#pragma once
// `suite check --baseline BASE.json RUN.json`: the CI regression gate. Every figure has a
// direction (bandwidth higher is better; latency, counts and energy lower is better); a point
// regresses when its median is worse than the baseline's by more than the tolerance plus the
// combined spread of the two runs' repetitions. A point either run flagged unstable is
// inconclusive, not a pass nor a regression. Exit 0: nothing regressed; 1: something did;
// 2: the input cannot be used.
#include <string>
#include <vector>

#include "harness/results/result_file.hpp"

namespace suite {

// inconclusive: the point was flagged unstable in the baseline or the run (the machine was busy,
// or its repetitions spread), so its change, whatever it is, says nothing; it never fails the gate.
enum class Verdict { regressed, improved, unchanged, inconclusive };

struct Finding {
    PointKey key;
    std::string figure;  // "bandwidth GB/s", "callgrind instructions per call", "verification"
    Direction direction = Direction::higher_is_better;
    double baseline = 0, run = 0;  // medians
    double worse_by = 0;           // relative: 0.3 = 30 % worse (negative: better)
    double allowed = 0;            // tolerance + spread, relative
    Verdict verdict = Verdict::unchanged;
    std::string note;  // e.g. "failed verification"
};

struct CheckReport {
    std::string baseline_path, run_path;
    double tolerance = 0.10;
    std::vector<Finding> findings;  // every figure compared
    std::size_t points_compared = 0;
    std::vector<PointKey> missing_from_run, not_in_baseline;
    std::vector<std::string> notes;  // context differences and anything else worth knowing
    std::size_t count(Verdict v) const;
};

// worse_by and the threshold for one figure; the verdict follows from them.
Finding judge(const Measure& baseline, const Measure& run, double tolerance);

// Compares every point of `run` with the same point of `baseline`. Throws InputError when no
// point of the run is in the baseline, or they share no figure.
CheckReport check_run(const ResultFile& baseline, const ResultFile& run, double tolerance);

std::string render_check_text(const CheckReport& report);
std::string render_check_markdown(const CheckReport& report);

// "10%", "10" (both 10 %), "2.5%"; throws UsageError for anything else or outside 0..1000 %.
double parse_tolerance(const std::string& text);
}  // namespace suite
