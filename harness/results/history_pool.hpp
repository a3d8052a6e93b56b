#pragma once
// The noise model of one machine and build: its series share their runs, and much of what moves
// one run moves every point of it (this VM's memory changes state from run to run), so each
// series' spread is pooled with the others' instead of being guessed from its own few runs.
//
// Each series' own spread s_i (Qn of its window's log medians, d_i degrees of freedom:
// history_scale.hpp) is shrunk toward the machine's, as limma shrinks gene variances (Smyth
// 2004): s_i^2 is taken as sigma_i^2 chi^2_{d_i} / d_i, and sigma_i^2 as drawn from a scaled
// inverse chi-square of d0 degrees of freedom about s0^2. d0 and s0 come from the series
// themselves by moments of log s_i^2: the more their spreads differ beyond what d_i allows, the
// smaller d0 and the less pooling. The pooled spread is (d0 s0^2 + d_i s_i^2) / (d0 + d_i), and a
// t interval built on it has d0 + d_i degrees of freedom.
//
// What pooling really gives: the series are not independent, since their runs share the
// machine's state. The pooled variance of S series of d degrees of freedom each whose residuals
// correlate by rho_ij has the variance of one of d S^2 / sum_ij rho_ij^2 degrees of freedom
// (normal residuals: Cov(s_i^2, s_j^2) = 2 rho_ij^2 sigma^4 / d). So d0 is capped at the sum of
// the d_i over 1 + (S - 1) times the mean rho_ij^2 of the pairs: S series that move together
// count as one. The correlations are measured on the runs the series share (residuals from each
// series' centre, in units of its own spread, clipped at 2.5 so that a stray run cannot make two
// series look alike), adjusted for their small-sample bias; a pair sharing fewer than 3 runs
// counts as fully correlated.
//
// The machine's jumps. This VM flips between states: for some runs every point is 15 to 30 %
// slower while each run's repetitions agree, and a window of runs that happened to agree at one
// point gives it a band far narrower than that. A robust spread (Qn) is blind to such runs by
// design, and the pooled one too, since the series' own spreads differ thirtyfold. So the runs are
// looked at one by one: a run whose log median lies farther from the median of its series' other
// runs than jump_sigmas (4) times that distance's spread under the series' pooled spread is a
// jump, a state of the machine. The jumps of every series of the figure are pooled, and each
// band of the figure is that of a mixture (RunBand::half_for): with the jumps' share of all the
// windows' runs, the next run is one of the jumps seen, on the side it would leave by, give or
// take the series' own noise and the machine's typical spread (the next jump is not exactly one
// seen); otherwise its own noise alone. A window without a jump changes nothing; a
// machine that changed state in the window has all its bands widened to take the change in, the
// calm series' included, and no wider. On four sets of 37 runs of this VM this took the A/A false
// alarms from 1, 0, 3 and 3 of 36 pairs to 1, 0, 1 and 1 (docs/results-tools.md).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace suite {

// One series' window: its runs' medians (in the figure's units) and the runs they came from.
struct SeriesWindow {
    std::vector<double> medians;
    std::vector<std::int64_t> runs;
};

// A run farther from its series' other runs than this many spreads is a jump (above). Under
// normal noise a run strays that far once in 16000, so a jump is a state, not the tail of the
// spread, and a jump seen widens every band of the figure only where the machine did jump.
inline constexpr double jump_sigmas = 4;

struct PooledSpread {
    double own = NAN, own_df = 0;  // the series' own Qn of its log medians, and its degrees of freedom
    double sigma = NAN, df = 0;    // pooled with the machine's: what its band is built on
    // The machine's jumps (below), the same for every series of the figure: their distances (log
    // units; sorted, at most 32 standing for them all), their share of all the windows' runs, and
    // the machine's typical spread (the median of the figure's pooled spreads), which a jump's
    // landing is given beside the series' own.
    std::vector<double> jumps;
    double jump_rate = 0;
    double jump_spread = 0;
};

struct MachineNoise {
    double prior = NAN;   // s0: the machine's typical spread (log units)
    double prior_df = 0;  // d0, after the cap
    double shared = NAN;  // mean correlation of the series' residuals: the share of between-run noise they share
    double effective_series = 0;  // S / (1 + (S - 1) mean rho^2)
    std::vector<double> jumps;    // the distances (log units) of the windows' runs that jumped
    std::size_t jump_runs = 0;    // the runs looked at
    double largest_jump() const;
    std::vector<PooledSpread> series;  // one per window, in order
};

// The pooled spreads of `windows` (one machine, build and figure). A window with fewer than
// `min_runs` medians, or one that is not positive, gets no spread (sigma NAN) and adds nothing.
// Fewer than 3 windows with a spread: no pooling (d0 = 0), each series its own; the jumps are
// looked for all the same.
MachineNoise pool_spreads(const std::vector<SeriesWindow>& windows, std::size_t min_runs);

// How many independent tests a run's figures amount to, for the Bonferroni family of a run that
// gates them all (band_alpha). `points`: the windows of each point's figures. The figures of one
// point are measured on the same repetitions and move together (a rate and the task-clock of the
// same repetitions are one test, not two); each point's count is Galwey's (2009) effective
// number, (sum_i sqrt(l_i))^2 / sum_i l_i over the eigenvalues l_i of its figures' correlation
// matrix (1 for figures that move as one, n for n that are independent), summed over the sets of
// figures that correlate (the ratio is not additive: a pair that moves as one beside two figures
// apart is 2.9 taken whole, 3 taken apart). At the tail probabilities a gate uses it is a little
// below the exact count for two normal figures (1.14 against 1.17 at r = 0.99 and 0.5 % a figure;
// bench: scipy's bivariate normal), less than the lower bound below gives back. Each correlation is that
// of the residuals of the runs the two share, taken at its 75 % lower bound in size (Fisher's z);
// a pair sharing fewer than 4 runs, or a series that never moves, at 0. Points are counted as
// independent of each other, though the machine's slow states move them together: six runs
// cannot tell how much, and a point alone is the conservative count. 0 for no figure.
double effective_figures(const std::vector<std::vector<SeriesWindow>>& points, std::size_t min_runs);

}  // namespace suite
