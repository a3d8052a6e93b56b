#pragma once
// `suite check --baseline BASE.json RUN.json`: the CI regression gate. Every figure has a
// direction (bandwidth higher is better; latency, counts and energy lower is better). The rule,
// per figure, has four outcomes:
//   - the change is within the minimum effect (the tolerance): unchanged;
//   - beyond it, and the repetitions of the two runs tell the runs apart (a one-sided
//     Mann–Whitney test at `alpha`): regressed or improved;
//   - beyond it, but the repetitions cannot tell (too few, or overlapping): inconclusive;
//   - a point either run flagged unstable (the machine was busy): inconclusive.
// Figures without repetitions (counters, energy: only min/median/max are kept) fall back to
// tolerance + the runs' combined spread. Counts of fewer than `min_count` events a repetition in
// both runs are not gated by ratio (0 -> 1 context switch is not infinitely worse). Exit 0:
// nothing regressed; 1: something did; 2: the input cannot be used.
#include <cmath>
#include <string>
#include <vector>

#include "harness/results/result_file.hpp"

namespace suite {

// inconclusive: the point was flagged unstable in the baseline or the run (the machine was busy,
// or its repetitions spread), so its change, whatever it is, says nothing; it never fails the gate.
enum class Verdict { regressed, improved, unchanged, inconclusive };

struct Finding {
    PointKey key;
    std::string host;    // the run's host of a rank record of an MPI run; "" otherwise
    std::string figure;  // "bandwidth GB/s", "callgrind instructions per call", "verification"
    Direction direction = Direction::higher_is_better;
    double baseline = 0, run = 0;  // medians
    double worse_by = 0;           // relative: 0.3 = 30 % worse (negative: better)
    double allowed = 0;            // the minimum effect (the tolerance; plus the spread without samples)
    Verdict verdict = Verdict::unchanged;
    // With repetitions in both files: the one-sided Mann–Whitney p-value in the direction of the
    // change, and a 95 % bootstrap interval of run / baseline (medians). NAN / tested=false without.
    bool tested = false;
    double p = NAN;
    double ratio_low = NAN, ratio_high = NAN;
    std::string note;  // e.g. "failed verification"
    // Gated against a history (history_band.hpp): the band of the runs' medians, and how many runs it came from.
    double band_low = NAN, band_high = NAN;
    std::size_t band_runs = 0;
};

// The decision rule's settings.
struct GateRule {
    double tolerance = 0.10;  // the minimum effect, relative
    double alpha = 0.01;      // one-sided significance level of the test
    double min_count = 100;   // events a repetition below which a count is not gated by ratio
};

struct CheckReport {
    std::string baseline_path, run_path;
    GateRule rule;
    std::vector<Finding> findings;  // every figure compared
    std::size_t points_compared = 0;
    std::vector<PointKey> missing_from_run, not_in_baseline;
    std::vector<std::string> notes;  // context differences and anything else worth knowing
    std::string rule_text;           // how the figures were judged, where not check's own rule (history check)
    std::size_t count(Verdict v) const;
};

// The verdict on one figure (key and unstable flags are the caller's).
Finding judge(const Measure& baseline, const Measure& run, const GateRule& rule);
inline Finding judge(const Measure& baseline, const Measure& run, double tolerance) {
    return judge(baseline, run, GateRule{tolerance});
}

// Compares every point of `run` with the same point of `baseline`. Throws InputError when no
// point of the run is in the baseline, or they share no figure, and when the two contexts differ
// in a field that makes their points incomparable (naming the fields) unless `force`, in which
// case the difference is a note.
CheckReport check_run(const ResultFile& baseline, const ResultFile& run, const GateRule& rule, bool force = false);

std::string render_check_text(const CheckReport& report);
std::string render_check_markdown(const CheckReport& report);
// For a pull request: only what changed, in at most 30 lines however many points: the
// regressions and improvements (the first 10), a count of the unchanged and inconclusive
// figures, the notes counted, and `steps` (one line each: the first 5, then how many more).
std::string render_check_summary_markdown(const CheckReport& report, const std::vector<std::string>& steps);

// "10%", "10" (both 10 %), "2.5%"; throws UsageError for anything else or outside 0..1000 %.
double parse_tolerance(const std::string& text);
// --alpha: a probability in (0, 0.5]; throws UsageError otherwise.
double parse_alpha(const std::string& text);
}  // namespace suite
