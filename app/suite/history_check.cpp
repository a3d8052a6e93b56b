// `suite history check` and `suite history noise`: the gate against the recent past, and the
// false alarms that gate would have raised on the stored runs (harness/results/history_gate,
// history_band, history_noise).
#include <algorithm>
#include <cmath>
#include <iostream>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "app/suite/history_args.hpp"
#include "harness/common/output_file.hpp"
#include "harness/common/units.hpp"
#include "harness/results/check.hpp"
#include "harness/results/history_gate.hpp"
#include "harness/results/history_noise.hpp"
#include "harness/results/text_table.hpp"

namespace suite {
namespace history_command {
namespace {

const char* const history_check_examples = R"EX(
The run against the recent history of its own machine, build and points. For each figure of each
point, the last N stable runs of its series (N = --window; its latest runs, flagged or not, where
fewer than 5 are stable), leaving out runs of the run's own commit, are pooled: their repetitions
together, and the band of their medians (how far one run strays from the others: the t
prediction interval of the log medians, their Qn spread pooled with the machine's other series of
the figure, at alpha shared among the run's figures, widened where the run's own repetitions
spread more than the window's did). A change regresses (or improves) when the run's median leaves
the band and is beyond the minimum effect: --tolerance, or with --tolerance=auto the band's own
edge (at least 1 %). Outside the band but inside its widening is inconclusive, saying the median
and repetitions that would tell. A series with fewer than 5 runs in the window has no band and is
gated by check's rule (at 25 % under auto); the output says which, and how many runs it needs. --base-commit SHA (a pull request's merge-base) pools that commit's runs
instead of the latest of any branch, and keeps the window's runs for the spread. --confirm RUN2,
a rerun of the same build: the two runs' mean is judged against the band for a mean of two, and a
change counts only where both runs moved that way (a machine's stray run moves the mean by half
and not the other run; a change of the code is in both, and their mean has less of the noise).

Examples:
  ./suite history check run.json
  ./suite history check run.json --tolerance=auto --confirm run2.json --markdown=gate.md
  ./suite history check run.json --base-commit "$(git merge-base origin/main HEAD)" --tolerance=auto
  ./suite history add run.json && ./suite history check run.json    # its own commit is left out

Exit status: 0 nothing regressed; 1 something regressed; 2 the run or the database cannot be
used, the history has no run of this machine and build to compare with, --base-commit has no run
of this machine and build, --confirm is not a rerun of the same build, or --markdown cannot be
written.
)EX";

const char* const history_noise_examples = R"(
For every series, how much its runs' medians move from run to run (the spread the gate's band is
made of) and how often the gate would have called an unchanged run regressed: each stable run is
left out in turn and gated against the --window runs nearest to it, with the rule and tolerance
of history check. On a history of unchanged reruns every regression found is a false alarm; on a
real history the steps count too, so the rate is an upper bound. --without-band gates with the
pooled window alone (the rule before the band), to compare; --confirm gates each run with the
next as its confirming rerun, both left out.

Examples:
  ./suite history noise
  ./suite history noise --tolerance=auto --confirm --kernel triad
  ./suite history noise --tolerance=25% --without-band     # the old rule, on the same runs

Exit status: 0; 2 the database cannot be used or a filter matches nothing.
)";

// The steps of `series`, one line each, for the pull request's summary.
std::vector<std::string> step_lines(const std::vector<Series>& series) {
    std::vector<std::string> out;
    for (const auto& s : series)
        for (const Step& st : detect_steps(s))
            out.push_back("`" + s.key.label() + "` " + s.figure + " " + s.unit + ": " + signed_percent(st.change) +
                          " from commit " + st.commit + (st.worse ? " (worse)" : " (better)"));
    return out;
}

// Why --base-commit found nothing: the commit is not there at all, or only with other builds.
[[noreturn]] void no_base_runs(const History& h, const RunIdentity& id, const std::string& base) {
    SeriesFilter f;
    f.fingerprints = {id.fingerprint};
    std::set<std::string> builds;
    for (const auto& s : h.series(f))
        for (const auto& e : s.entries)
            if (same_commit(e.commit, base)) builds.insert(s.context_class);
    if (builds.empty())
        throw InputError(h.path() + ": no run of --base-commit " + base + " on " + id.machine +
                         "; add the base's runs first (run the gate on it), "
                         "or leave out --base-commit to gate against the latest runs");
    std::string list;
    for (const auto& b : builds) list += (list.empty() ? "" : "; ") + b;
    throw InputError(h.path() + ": the runs of --base-commit " + base + " on " + id.machine +
                     " are of another build (" + list + "), not " + id.context_class +
                     "; gate builds of one kind against each other");
}

}  // namespace

int history_check(const std::vector<std::string>& args) {
    CLI::App app{"suite history check: gate a run against the recent history of its machine, build and points"};
    app.footer(history_check_examples);
    HistoryArgs a;
    std::vector<std::string> runs;
    std::string commit, tolerance = "10%", alpha = "0.01", base_commit, markdown, confirm;
    unsigned window = 10;
    app.add_option("run", runs, "the result file of the run to gate");
    app.add_option("--confirm", confirm,
                   "a rerun of the same build: the two runs' mean is judged, and a change counts only where both "
                   "runs show it");
    add_db_options(app, a);
    add_whole_option(app, "--window", window, 1, 1000,
                     "how many of the most recent runs of each series to pool (default 10)");
    app.add_option("--tolerance", tolerance,
                   "the smallest change that counts, in percent, or auto: each series' band edge (default 10%)");
    app.add_option("--alpha", alpha,
                   "significance level of the one-sided test on the repetitions and of the band (default 0.01)");
    app.add_option("--commit", commit, "the run's commit, left out of the window (default: its git_revision)");
    app.add_option("--base-commit", base_commit,
                   "pool this commit's runs (a pull request's merge-base) instead of the latest runs");
    app.add_option("--markdown", markdown, "also write a short Markdown summary to FILE (for the pull request)");
    if (!parse_command_line(app, "suite history check", args)) return 0;
    if (runs.size() != 1)
        throw UsageError("history check needs exactly one run file, e.g. ./suite history check run.json");
    HistoryRule rule;
    parse_history_tolerance(tolerance, rule);
    rule.gate.alpha = parse_alpha(alpha);
    rule.confirmed = !confirm.empty();
    base_commit = commit_option(base_commit, "--base-commit");
    commit = commit_option(commit, "--commit");
    OutputFile md;
    if (!markdown.empty())
        md = OutputFile::claim(markdown, "--markdown",
                               identify_inputs({runs[0], a.db, confirm.empty() ? runs[0] : confirm}));
    const ResultFile run = load_result_file(runs[0]);
    if (!run.complete)
        throw InputError(run.path + ": the run was interrupted (\"complete\": false); gate only complete runs");
    ResultFile rerun;
    if (!confirm.empty()) {
        rerun = load_result_file(confirm);
        if (!rerun.complete)
            throw InputError(rerun.path +
                             ": the run was interrupted (\"complete\": false); confirm with a complete rerun");
        const RunIdentity x = identify_run(run, commit), y = identify_run(rerun, commit);
        if (x.fingerprint != y.fingerprint || x.context_class != y.context_class || x.commit != y.commit)
            throw InputError("--confirm " + rerun.path + ": not a rerun of " + run.path + " (" +
                             (x.fingerprint != y.fingerprint ? "machine " + y.machine + " against " + x.machine
                              : x.context_class != y.context_class
                                  ? "build " + y.context_class + " against " + x.context_class
                                  : "commit " + y.commit + " against " + x.commit) +
                             "); confirm with a second run of the same build on the same machine");
    }
    const History h = History::open_for_reading(a.db, history_options(a));
    const RunIdentity id = identify_run(run, commit);
    SeriesFilter f;
    f.fingerprints = {id.fingerprint};
    f.context_class = id.context_class;
    const std::vector<Series> series = h.series(f);
    const std::string label =
        h.path() + " (" +
        (base_commit.empty() ? "the last " + std::to_string(window) + " runs" : "the runs of commit " + base_commit) +
        " of each point on " + id.machine + ", commit " + id.commit + " left out)";
    const WindowBaseline base =
        window_baseline(series, run, id, h.find_run(run_content_hash(run)), window, label, base_commit);
    if (base.file.points.empty()) {
        if (!base_commit.empty()) no_base_runs(h, id, base_commit);
        throw InputError(h.path() + ": no run of this machine (" + id.machine + ") and build (" + id.context_class +
                         ") besides commit " + id.commit + " has any point of " + run.path +
                         "; add such runs first (./suite history add)");
    }
    std::size_t most_runs = 0;
    for (const auto& [key, m] : base.medians) most_runs = std::max(most_runs, m.window.size());
    if (rule.auto_tolerance && most_runs < rule.min_runs)
        throw InputError(h.path() + ": --tolerance=auto needs " + std::to_string(rule.min_runs) +
                         " runs of a point in the window to measure its spread; " + "the most any point of " +
                         run.path + " has is " + std::to_string(most_runs) + "; add " +
                         std::to_string(rule.min_runs - most_runs) + " more run(s), or give --tolerance=25%");
    // Same machine and build by construction; the one difference check_run could find is which
    // huge-page settings the points asked for, when only some of the run's points have history.
    // The rerun has the run's commit, so the window leaves it out as it leaves out the run.
    CheckReport rep = gate_with_bands(base, run, rule, confirm.empty() ? nullptr : &rerun);
    if (!confirm.empty()) note_confirmation(rep, rerun.path);
    rep.notes.insert(rep.notes.begin(), std::to_string(base.runs_pooled) + " run(s) of the history pooled");
    rep.notes.insert(rep.notes.end(), run.notes.begin(), run.notes.end());
    if (md.claimed()) {
        try {
            md.write(render_check_summary_markdown(rep, step_lines(series)));
        } catch (const std::exception& e) {
            throw UsageError(e.what());
        }
    }
    std::cout << render_check_text(rep) << std::flush;
    return rep.count(Verdict::regressed) ? 1 : 0;
}

int history_noise(const std::vector<std::string>& args) {
    CLI::App app{
        "suite history noise: each series' spread between runs and the gate's false alarms on the stored runs"};
    app.footer(history_noise_examples);
    HistoryArgs a;
    std::string tolerance = "10%", alpha = "0.01";
    unsigned window = 10;
    bool without_band = false, confirm = false;
    add_db_options(app, a);
    add_filter_options(app, a);
    add_whole_option(app, "--window", window, 1, 1000, "how many runs each left-out run is gated against (default 10)");
    app.add_option("--tolerance", tolerance, "the smallest change that counts, in percent, or auto (default 10%)");
    app.add_option("--alpha", alpha, "as history check's (default 0.01)");
    app.add_flag("--without-band", without_band, "gate with the pooled window alone, the rule before the band");
    app.add_flag("--confirm", confirm,
                 "gate each run with the next one as its confirming rerun, as history check --confirm");
    if (!parse_command_line(app, "suite history noise", args)) return 0;
    HistoryRule rule;
    parse_history_tolerance(tolerance, rule);
    rule.gate.alpha = parse_alpha(alpha);
    if (without_band && rule.auto_tolerance)
        throw UsageError(
            "--tolerance=auto needs the band; give a percentage with --without-band, e.g. --tolerance=25%");
    const History h = History::open_for_reading(a.db, history_options(a));
    const std::vector<Series> series = filtered_series(h, a);
    const NoiseReport rep = measure_noise(series, window, rule, !without_band, confirm);
    const std::string how =
        (without_band ? "the pooled window alone at " + tolerance
                      : "the band of " + std::to_string(window) + " runs" +
                            (rule.auto_tolerance ? ", --tolerance=auto" : ", --tolerance=" + tolerance)) +
        (confirm ? ", each confirmed by the next run" : "");
    std::cout << h.path() << ": " << series.size() << " series; leaving each run out and gating it (" << how
              << "): " << rep.runs_alarmed.size() << " of " << rep.runs_tried.size()
              << " run(s) called regressed somewhere\n";
    std::map<std::pair<std::string, std::string>, TextTable> tables;
    std::vector<std::pair<std::string, std::string>> order;
    for (const SeriesNoise& n : rep.series) {
        const Series& s = *n.series;
        const auto group = std::make_pair(s.machine + " [" + s.fingerprint + "]", s.context_class);
        auto [it, fresh] =
            tables.try_emplace(group, TextTable{{"point", "figure", "runs", "spread", "pooled (df)", "sd",
                                                 "next run's band", "left out", "regressed", "improved"},
                                                {},
                                                {false, false, true, true, true, true, false, true, true, true}});
        if (fresh) order.push_back(group);
        const std::string band =
            n.band.usable() ? "[" + format_significant(n.band.low, 4) + ", " + format_significant(n.band.high, 4) + "]"
                            : "none: " + no_band_reason(n.band, rule.min_runs);
        auto pc = [](double x) { return std::isfinite(x) ? format_significant(x * 100, 2) + "%" : std::string("-"); };
        it->second.rows.push_back(
            {s.key.label(), s.figure + " " + s.unit, std::to_string(s.entries.size()), pc(n.band.own_spread),
             pc(n.band.spread) + " (" + format_significant(n.band.df, 3) + ")", pc(n.sd_spread), band,
             std::to_string(n.tried), std::to_string(n.regressed), std::to_string(n.improved)});
    }
    for (const auto& g : order) std::cout << "\n" << g.first << ", " << g.second << ":\n" << tables.at(g).render_text();
    std::cout << "\n";
    for (const PoolNoise& p : rep.pools) {
        const MachineNoise& m = p.noise;
        std::size_t with = 0;
        for (const PooledSpread& s : m.series) with += std::isfinite(s.sigma);
        std::cout << p.first->machine << ", " << p.first->context_class << ", " << p.first->figure << " "
                  << p.first->unit << ": "
                  << (m.prior_df > 0
                          ? "the spreads of " + std::to_string(with) + " series pooled (the machine's " +
                                format_significant(m.prior * 100, 2) + "%, worth " + format_significant(m.prior_df, 3) +
                                " degrees of freedom); their runs' noise correlates " +
                                (std::isfinite(m.shared) ? format_significant(m.shared, 2) : "-") + ", as " +
                                format_significant(m.effective_series, 2) + " independent series"
                          : std::to_string(with) + " series with a spread: each its own (pooling needs 3)")
                  << (!m.jumps.empty()
                          ? "; " + std::to_string(m.jumps.size()) + " of the windows' " + std::to_string(m.jump_runs) +
                                " runs jumped (up to " + format_significant((std::exp(m.largest_jump()) - 1) * 100, 2) +
                                "%): every band takes such a jump in"
                          : std::string())
                  << "\n";
    }
    std::cout << "\nspread: Qn of the runs' log medians (relative), pooled with the machine's series of the same "
                 "figure; sd: their standard deviation, larger where a stray run is in the window; the band is what "
                 "history check accepts of the next run.\n"
              << std::flush;
    return 0;
}

}  // namespace history_command
}  // namespace suite
