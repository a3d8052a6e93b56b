#pragma once
// The between-run model of one series: how far one run's median strays from the runs before it.
// A run's repetitions are taken seconds apart, so they show the noise within a run; a machine
// also moves between runs (this VM's memory bandwidth changes state from run to run while each
// run's repetitions stay tight), and only the runs' medians show that. From the medians of the
// window's runs: the centre is the median of their logarithms; the spread is Qn of them
// (history_scale.hpp: robust to a stray run, and worth d degrees of freedom), pooled with the
// other series of the machine where there are some (history_pool.hpp: d0 + d degrees of freedom);
// the band is the Student-t prediction interval for one more run, centre +- t(1 - a/2, df) *
// spread * sqrt(1 + 1/m), with m runs for the centre (the window's, or the base commit's with
// --base-commit); where the machine jumped in the window, the band of a mixture that takes the
// jumps in (history_pool.hpp, RunBand::half_for). `a` is the gate's alpha shared among the
// figures the run gates (band_alpha below: Bonferroni).
//
// A run whose own repetitions spread more than the window's runs' did (an unstable point, a DRAM
// point of 5 repetitions here) has a median that is less sure than theirs: its band is widened
// by that excess, the square of its median's standard error beyond the window's typical one
// (median_standard_error), added to the spread's square. A median outside the band but inside
// the widened one is inconclusive, and says the figure and the repetitions it would need.
//
// This VM's medians have heavy tails: about one run in four is 20 to 45 % off at some point, every
// repetition of it agreeing, with nothing changed. No band of one run absorbs that and still sees
// a 1.25x slowdown, so the spread is a robust one, and a stray run is told from a change by a
// second run: with --confirm, the mean of the run and a rerun of the same build is judged, and a
// figure regresses only where both runs moved that way (judge_pair; docs/results-tools.md).
#include <cmath>
#include <cstddef>
#include <string>
#include <vector>

#include "harness/results/check.hpp"

namespace suite {

// How `history check` and `history noise` judge a figure against its history.
struct HistoryRule {
    GateRule gate;                // the minimum effect (tolerance), alpha and min_count of check
    bool auto_tolerance = false;  // --tolerance=auto: the minimum effect is the band's edge
    double auto_floor = 0.01;     // ...never below 1 %
    // A series with fewer runs than the model needs is gated by check's rule at this tolerance
    // under --tolerance=auto (the A/A reruns of docs/results-tools.md: no false alarm at 25 %).
    double fallback_tolerance = 0.25;
    std::size_t min_runs = 5;  // runs the band needs (the spread of 4 logarithms says little)
    bool confirmed = false;    // --confirm: judged with a rerun (judge_pair)
};

// The two-sided chance a band leaves to one figure, for a run that gates `family` figures (as
// independent tests: effective_figures, history_pool.hpp; at least 1):
// 2 · alpha / family (Bonferroni), with or without a confirming rerun. Were two runs independent,
// a confirmed gate could take 2 · sqrt(alpha / family) for the same guarantee (both runs stray at
// one figure with its square), bands four times narrower at 90 figures; but this VM's slow states
// last minutes, consecutive runs share them, and at that share the confirmed gate false-alarmed on
// 2 of 13 and 2 of 11 left-out pairs against 0 of 13 and 1 of 11 at this one
// (docs/results-tools.md). The rerun stays a second line of defence, not a licence.
double band_alpha(double alpha, double family);

// How the noise of a run and its rerun, taken seconds apart, is taken to correlate when their
// mean is judged (judge_pair). The log medians of consecutive runs 2 to 4 s apart on this VM
// correlated -0.45 to 0.45 (12 series of 37 runs, mean 0.13; docs/results-tools.md): 0.5 stands
// above every one, so that the band for the pair is narrower than a run's by a factor of at most
// sqrt((0.75 + 1/m) / (1 + 1/m)), 0.89 at m = 6 runs, where runs that shared a slow state fully
// would need the run's own.
inline constexpr double rerun_correlation = 0.5;

struct RunBand {
    std::size_t runs = 0;          // medians the spread was estimated from
    std::size_t centre_runs = 0;   // medians the centre was taken from
    double centre = NAN;           // in the figure's units
    double own_spread = NAN;       // relative (log units): Qn of the window's log medians
    double spread = NAN;           // the same, pooled with the machine's where it was (else own_spread)
    double df = 0;                 // the degrees of freedom of `spread`
    double quantile = NAN;         // t(1 - a/2, df)
    double half_width = NAN;       // of the band, in log units; NAN: no band (too few runs)
    double low = NAN, high = NAN;  // the band, in the figure's units
    // The typical standard error of a window run's median from its own repetitions (log units);
    // NAN: not known (no repetitions stored), taken as 0, so that a run is widened by all of its own.
    double typical_se = NAN;
    // The variance of the judged median in units of one run's: 1 for a run, (1 + rho) / 2 for
    // the mean of a run and its rerun whose noise correlates rho (for_pair).
    double run_share = 1;
    double alpha = NAN;  // the two-sided chance the band leaves an unchanged run
    // The machine's jumps in the window (history_pool.hpp): their distances (log units, sorted,
    // at most 32) and their share of the windows' runs. Whole for a pair too: a run and its
    // rerun share the machine's state.
    std::vector<double> jumps;
    double jump_rate = 0;
    double jump_spread = 0;  // the machine's typical spread, beside the run's own for a jump
    bool usable() const { return std::isfinite(half_width); }
    // The band for the mean of the log medians of a run and its rerun (rerun_correlation).
    RunBand for_pair() const;
    // The variance, in log units squared, of the judged median's distance from the centre that
    // the runs' spread accounts for: spread^2 (run_share + 1/m), m the centre's runs.
    double runs_variance() const;
    // The half-width at `alpha` for a run whose distance from the centre has the variance
    // runs_variance() + extra beside the machine's jumps: quantile * sqrt(that) without jumps;
    // with them, the h at which a mixture leaves alpha out, and never less than without. With
    // the jumps' share p, the run is one of the k jumps seen (each as likely, on the side it would
    // leave by) plus that noise and jump_spread, c_j = sqrt(c^2 + jump_spread^2); otherwise the
    // noise alone, c = sqrt(runs_variance() + extra); both a t of df degrees of freedom, S its tail:
    // (1 - p) 2 S(h / c) + p / k sum_j (S((h - j) / c_j) + S((h + j) / c_j)) = alpha.
    // On a simulated machine 20 % slower one run in five, over the windows that saw it: 0.69 % of
    // unchanged runs false-alarm at alpha 1 % (18.5 % without the jumps; without jump_spread,
    // about 2 %), and a 1.5x at the calmest series is caught in 91 % (96 %; history_pool_test.cpp).
    double half_for(double extra) const;
    // The half-width for a run whose median has standard error `se` (NAN: unknown): the band's,
    // widened by what `se` exceeds typical_se.
    double widened(double se) const;
};

// The standard error of a median of `n` repetitions whose relative spread is `noise`, in log
// units: sqrt(pi / 2) noise / sqrt(n) (a median's, for normal repetitions). NAN for n < 2 or no noise.
double median_standard_error(double noise, std::size_t n);

struct PooledSpread;

// The band of a series. `window`: the medians the spread is estimated from; `centre`: the ones
// the centre is taken from (empty: the window's). `alpha`: the chance, for this one figure, that
// an unchanged run leaves it (two-sided). `pooled`: the series' spread pooled with its machine's
// (history_pool.hpp); null or without a spread: the window's own. Fewer than `min_runs` window
// medians, or any that is not positive: no band (half_width NAN), the centre still set where
// there is one.
RunBand fit_band(const std::vector<double>& window, const std::vector<double>& centre, double alpha,
                 std::size_t min_runs, const PooledSpread* pooled = nullptr);

// "fewer than 5 runs in the window (3): 2 more run(s) needed for a band", or why else there is none.
std::string no_band_reason(const RunBand& band, std::size_t min_runs);

// One figure of a run against its history: `base` pooled from the runs (history_gate.hpp), the
// band fitted from their medians. With a band, the baseline's median is the band's centre, the
// minimum effect is --tolerance (or the floor under auto), and a change regresses or improves
// where it is beyond that and the run's median lies outside the band widened by the run's own
// repetitions (RunBand::widened; the finding's band_low/high); the Mann-Whitney p of check's
// rule is reported, not required. `allowed` is the larger of the minimum effect and that band's
// edge on the worse side. Outside the band but inside the widened one: inconclusive, the note
// naming the median and the repetitions that would tell. Without a band, check's own judge at
// --tolerance (at fallback_tolerance under auto), and the note says so.
Finding judge_with_band(const Measure& base, const Measure& run, const RunBand& band, const HistoryRule& rule);

// --confirm: a run and its rerun judged together. With a band: the mean of their log medians (the
// geometric mean; for the widening, their repetitions, each run's scaled onto it) against the band for a pair
// (RunBand::for_pair), and a change counts only where each of the two runs moved that way by
// more than the minimum effect; otherwise inconclusive, the note giving both changes. One stray
// run, however far, moves the mean by half its distance and not the other run; a change of the
// code moves both, and their mean has less of the runs' noise than either (a 1.5x slowdown at
// 64 MiB, caught in 10 to 13 pairs of 36 when each run had to leave the band alone, was caught in
// 24 and 25 this way, with no false alarm in 108 unchanged pairs: docs/results-tools.md).
// Without a band: each run by judge_with_band, and the verdict stands only where both agree.
Finding judge_pair(const Measure& base, const Measure& run, const Measure& rerun, const RunBand& band,
                   const HistoryRule& rule);

// "auto", or a tolerance as parse_tolerance reads it; sets rule.auto_tolerance or rule.gate.tolerance.
void parse_history_tolerance(const std::string& text, HistoryRule& rule);

}  // namespace suite
