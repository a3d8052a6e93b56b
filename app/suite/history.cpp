// `suite history add|list|steps|check|noise|html`: their options and help; the work is in
// harness/results/ (history: the database; steps: step detection; history_gate: the window
// gate; history_band: the between-run band; history_noise: the measured false alarms;
// dashboard: the page).
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <map>
#include <set>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "app/suite/commands.hpp"
#include "app/suite/data_dir.hpp"
#include "app/suite/history_args.hpp"
#include "app/suite/parse.hpp"
#include "harness/results/check.hpp"
#include "harness/results/dashboard.hpp"
#include "harness/results/history.hpp"
#include "harness/results/steps.hpp"
#include "harness/results/text_table.hpp"

namespace suite {
namespace history_command {
namespace {

const char* const history_usage =
    R"(suite history: every run's results in one SQLite database; their steps; a gate against the recent past

  ./suite history add RUN.json... [--db FILE] [--commit SHA] [--branch NAME]
  ./suite history list  [--db FILE]
  ./suite history steps [--db FILE] [--kernel K] [--machine M]
  ./suite history check RUN.json [--db FILE] [--window N] [--tolerance 10%|auto] [--alpha 0.01]
                                 [--base-commit SHA] [--markdown FILE]
  ./suite history noise [--db FILE] [--window N] [--tolerance 10%|auto] [--kernel K] [--machine M]
  ./suite history html --out DIR [--db FILE] [--kernel K] [--machine M] [--window N] [--alpha 0.01]

The database is results/history.sqlite unless --db says otherwise. A series is one figure of one
point (kernel, variant, pattern, size, threads, pinning, placement, parameters) on one machine
(its fingerprint: host, CPU, sockets, NUMA nodes, cores, memory) built one way (compiler, flags,
build type, instruction set, THP, the point's huge pages), its runs in date order.
Each subcommand's --help has examples. Exit status 2, one line on stderr, when the database or
a file cannot be used (missing, corrupt, of a newer schema version, read-only for add, locked
for longer than --wait); the database is then left as it was.
)";

const char* const history_add_examples = R"(
Every figure of every point of each run is stored, with its repetitions, under the run's machine
fingerprint, build, commit (the file's git_revision unless --commit) and branch (--branch, else
$GITHUB_REF_NAME, else "unknown"). The files go in one transaction: all or none. A run already
there (the same measurements, however the file is named or formatted) is not stored again.
Interrupted runs ("complete": false) are refused.

Examples:
  ./suite history add results/latest.json
  ./suite history add ci-run.json --db /srv/perf/history.sqlite --branch main
  ./suite history add a.json b.json --commit 2ddd7e4d2055

Exit status: 0 added (or already there); 2 a file or the database cannot be used (one line).
)";

const char* const history_steps_examples = R"(
A step is a change of level that persists from one commit on: binary segmentation of each series
(stable runs only) with, at every split between two commits that leaves 3 runs or more on each
side, the two-sided Mann-Whitney test of the runs' medians before against after. A split is a
step when p times the number of splits tried (Bonferroni) is below 0.01 and the medians of the
two sides differ by 5 % or more; each side is then searched again. Where no single split is a
step, a stretch of commits that differs from both sides together (a regression fixed later) is
tested the same way. Each step names the commit of the first run at the new level.

Examples:
  ./suite history steps
  ./suite history steps --kernel add --machine ci-runner
  ./suite history steps --db /srv/perf/history.sqlite --machine 3f9a0c1d
)";

const char* const history_html_examples = R"(
A static page (DIR/index.html, with Chart.js beside it, from Debian's libjs-chart.js) that opens
from file:// with no network: a chart a series, the spread of its repetitions, the band of its
last --window runs that history check will hold the next run against (at --alpha, shared among
the series of a machine and build on the page, counted as the independent tests they amount
to), and its steps marked.

Examples:
  ./suite history html --out results/history-html
  ./suite history html --out /tmp/add --kernel add --machine ci-runner
)";

int history_add(const std::vector<std::string>& args) {
    CLI::App app{"suite history add: store runs in the history database"};
    app.footer(history_add_examples);
    HistoryArgs a;
    std::vector<std::string> paths;
    std::string commit, branch;
    app.add_option("runs", paths, "result files written by suite --out=FILE.json");
    add_db_options(app, a);
    app.add_option("--commit", commit, "the commit the runs were built from (default: each file's git_revision)");
    app.add_option("--branch", branch, "the branch (default: $GITHUB_REF_NAME, else unknown)");
    if (!parse_command_line(app, "suite history add", args)) return 0;
    if (paths.empty())
        throw UsageError("history add needs at least one result file, e.g. ./suite history add results/latest.json");
    commit = commit_option(commit, "--commit");
    if (branch.empty())
        if (const char* ci = std::getenv("GITHUB_REF_NAME"); ci && *ci) branch = ci;
    // Every file is read and checked before the database is opened: a bad one changes nothing.
    std::vector<ResultFile> files;
    for (const auto& p : paths) {
        files.push_back(load_result_file(p));
        if (!files.back().complete)
            throw InputError(p + ": the run was interrupted (\"complete\": false); add only complete runs");
        if (files.back().points.empty())
            throw InputError(p + ": the run has no results (\"results\": []); there is nothing to add");
    }
    History h = History::open_for_adding(a.db, history_options(a));
    for (const AddOutcome& o : h.add(files, commit, branch)) {
        if (o.added)
            std::cout << "added " << o.source << ": run " << o.run_id << ", commit " << o.stored_commit << " (branch "
                      << o.id.branch << "), " << o.figures << " figure(s); machine " << o.id.machine << " ["
                      << o.id.fingerprint << "], build " << o.id.context_class << "\n";
        else
            std::cout << o.source << ": already in the history as run " << o.run_id << " (commit " << o.stored_commit
                      << "); not added again\n";
    }
    std::cout << h.path() << ": " << h.run_count() << " run(s)\n" << std::flush;
    return 0;
}

int history_list(const std::vector<std::string>& args) {
    CLI::App app{"suite history list: the machines, builds and commits in the history database"};
    app.footer("\nExamples:\n  ./suite history list\n  ./suite history list --db /srv/perf/history.sqlite\n");
    HistoryArgs a;
    add_db_options(app, a);
    if (!parse_command_line(app, "suite history list", args)) return 0;
    const History h = History::open_for_reading(a.db, history_options(a));
    const auto machines = h.summary();
    std::cout << h.path() << " (schema version " << h.schema_version() << "): " << h.run_count() << " run(s) of "
              << machines.size() << " machine(s)\n";
    for (const auto& m : machines) {
        std::cout << "\nmachine " << m.machine << " [" << m.fingerprint << "]: " << m.runs << " run(s), " << m.series
                  << " series, " << m.context_classes << " build(s)\n";
        TextTable t{{"commit", "branch", "runs", "latest run"}, {}, {false, false, true, false}};
        for (const auto& c : m.commits) t.rows.push_back({c.commit, c.branch, std::to_string(c.runs), c.latest_date});
        std::cout << t.render_text();
    }
    std::cout << std::flush;
    return 0;
}

int history_steps(const std::vector<std::string>& args) {
    CLI::App app{"suite history steps: the changes of level in each series, and the commit where each began"};
    app.footer(history_steps_examples);
    HistoryArgs a;
    add_db_options(app, a);
    add_filter_options(app, a);
    if (!parse_command_line(app, "suite history steps", args)) return 0;
    const History h = History::open_for_reading(a.db, history_options(a));
    const std::vector<Series> series = series_with_steps(h, a);
    std::size_t found = 0;
    // One table a machine and build, in the series' order.
    std::map<std::pair<std::string, std::string>, TextTable> tables;
    std::vector<std::pair<std::string, std::string>> order;
    for (const auto& s : series) {
        for (const Step& st : s.steps) {
            const auto group = std::make_pair(s.machine + " [" + s.fingerprint + "]", s.context_class);
            auto [it, fresh] =
                tables.try_emplace(group, TextTable{{"point", "figure", "commit", "before", "after", "change", "", "p"},
                                                    {},
                                                    {false, false, false, true, true, true, false, true}});
            if (fresh) order.push_back(group);
            it->second.rows.push_back({s.key.label(), s.figure + " " + s.unit, st.commit, format_number(st.before),
                                       format_number(st.after), signed_percent(st.change),
                                       st.worse ? "worse" : "better", format_number(st.p)});
            ++found;
        }
    }
    std::cout << h.path() << ": " << found << " step(s) in " << series.size() << " series\n";
    for (const auto& g : order) std::cout << "\n" << g.first << ", " << g.second << ":\n" << tables.at(g).render_text();
    std::cout << std::flush;
    return 0;
}

int history_html(const std::vector<std::string>& args) {
    CLI::App app{"suite history html: a static page of the history's trends"};
    app.footer(history_html_examples);
    HistoryArgs a;
    std::string out, alpha = "0.01";
    unsigned window = 10;
    app.add_option("--out", out, "the directory to write index.html (and chart.min.js) into");
    add_db_options(app, a);
    add_filter_options(app, a);
    add_whole_option(app, "--window", window, 1, 1000,
                     "the runs each chart's band is fitted from, as history check's (default 10)");
    app.add_option("--alpha", alpha, "as history check's (default 0.01)");
    if (!parse_command_line(app, "suite history html", args)) return 0;
    if (out.empty())
        throw UsageError("history html needs --out=DIR, e.g. ./suite history html --out results/history-html");
    const History h = History::open_for_reading(a.db, history_options(a));
    const std::vector<Series> series = series_with_steps(h, a);
    std::size_t steps = 0;
    for (const auto& s : series) steps += s.steps.size();
    DashboardOptions options;
    options.title = "suite history: " + h.path();
    options.window = window;
    options.alpha = parse_alpha(alpha);
    // An installed tree carries its own copy of Chart.js (copied from Debian's when installed).
    if (data_dir().installed) {
        std::string why;
        options.chart_js = data_file("chart.min.js", why);
        if (options.chart_js.empty())
            throw UsageError(why +
                             "; the history page needs this copy of Chart.js, which make install takes from Debian's "
                             "libjs-chart.js");
    }
    std::cout << "wrote " << write_dashboard(series, out, options) << " (" << series.size() << " series, " << steps
              << " step(s))\n"
              << std::flush;
    return 0;
}

}  // namespace
}  // namespace history_command

int cmd_history(const std::vector<std::string>& args) {
    using namespace history_command;
    const std::string sub = args.empty() ? "" : args[0];
    const std::vector<std::string> rest(args.begin() + (args.empty() ? 0 : 1), args.end());
    if (sub == "add") return history_add(rest);
    if (sub == "list") return history_list(rest);
    if (sub == "steps") return history_steps(rest);
    if (sub == "check") return history_check(rest);
    if (sub == "noise") return history_noise(rest);
    if (sub == "html") return history_html(rest);
    if (sub == "--help" || sub == "-h" || sub == "help") {
        std::cout << history_usage;
        return 0;
    }
    if (sub.empty())
        throw UsageError(
            "history needs a subcommand: add, list, steps, check, noise or html (see ./suite history --help)");
    require_known({sub}, {"add", "list", "steps", "check", "noise", "html"}, "history subcommand");
    return 2;  // not reached: require_known threw
}

}  // namespace suite
