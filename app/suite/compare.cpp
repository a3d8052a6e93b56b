// `suite compare`: its options and help; the work is in harness/results/compare.cpp.
#include <iostream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "app/suite/commands.hpp"
#include "app/suite/frame.hpp"
#include "app/suite/parse.hpp"
#include "app/suite/plotter.hpp"
#include "harness/common/choice_table.hpp"
#include "harness/common/output_file.hpp"
#include "harness/results/compare.hpp"
#include "harness/results/compare_hosts.hpp"

namespace suite {
namespace compare_command {
namespace {

// compare's --format, one table; the behaviour is whether the comparison is written as Markdown.
const ChoiceTable<bool>& compare_formats() {
    static const ChoiceTable<bool> table{"--format",
                                         {{"table", "columns for the console, the default", false},
                                          {"markdown", "a Markdown table, e.g. for a pull request", true}}};
    return table;
}

const char* const compare_examples = R"(
Points are matched by kernel, variant, pattern or ordering, size, threads, pinning, placement
and kernel parameters (--tol=... and the like). A point run on all of its machine's CPUs
(--threads=all) matches the other machines' all-CPU points whatever their core counts. Points
of the default sweep carry the cache their size came from (L1/2 and L2/2: half an L1 or L2 per
thread; L3/2: half the last level, where --probe-caches measured it; DRAM): between machines
whose caches differ they match by that role, each file's size shown beside its figure, with a
geometric mean per role. Sizes given with --sizes match by size. A role one file has and
another lacks is refused (unless --force: the roles they share).
For each file: the best and median of the point's headline figure (GB/s for bandwidth kernels,
ns per load for latency, instructions for a deterministic run), and its ratio to the first file
as performance from the medians: above 1 is better than the first file, whichever way the
figure goes (for a bandwidth B/A, for a latency A/B), with a 95 % bootstrap interval of that
ratio from the repetitions. Then the geometric mean of those ratios per kernel. Before the
table: the context fields on which the files differ, each said to be of the machine (CPU,
sockets, NUMA nodes, cores, memory), of the build or settings (compiler and flags, build
type, the instruction set -march resolved to, THP, huge pages asked) or informational
(reported caches, governor). What -march=native resolved to is the machine's when every file
was built with it; a flag the user chose (-O2, -DNDEBUG, -march=x86-64-v3) is the build's.
Files that differ as machines and in the user's settings are refused, naming those settings
(a ratio could not say which made the difference), unless --force.

--plot DIR draws, per kernel, pattern and thread count (1, all), each file's bandwidth (or
latency) against footprint on one set of axes, each machine's caches marked in its colour,
unstable points hollow: DIR/compare-KERNEL-PATTERN-t1.png, ...-all.png (plots/compare.py).
DIR is checked before anything is read and claimed like any output (never over an input).

MPI runs (suite-mpi): a file holds each point once per rank and once as the aggregate of all
ranks. Two MPI runs of as many ranks match rank with rank and aggregate with aggregate (rows
say "rank 1 of 2 on HOST", "aggregate of 2 ranks"). A plain run's point matches only the
aggregate of an MPI run of one rank (one process either way); against a run of more ranks
the files have no point in common, and the error says so (N ranks against one process).
One MPI file alone lines up the hosts of that run: per point one column per host (for GB/s
the sum of its ranks' best, for ns/load its worst rank's best), each host's ratio to the
fastest host (1.000x; below 1 is slower), the slowest host named, the aggregate and its rank
spread, and the geometric mean of each host's ratios per kernel. A run on one host shows its
ranks instead of hosts. A single plain file is refused: there is nothing to line up.

Examples:
  ./suite compare results/epyc.json results/xeon.json          # two machines
  ./suite compare before.json after.json --format=markdown > comparison.md
  ./suite compare tests/fixtures/results/vm-native.json tests/fixtures/results/vm-x86-64-v3.json
  ./suite compare epyc-thp.json xeon-nothp.json --force          # both changed: listed, compared anyway
  ./suite compare epyc.json xeon.json --plot figures/             # and the figures
  ./suite compare cluster-mpi.json                                # one MPI run: its hosts side by side
  ./suite compare mpi-before.json mpi-after.json                  # two MPI runs, rank by rank

Exit status: 0 compared; 1 the figures could not be drawn (said on stderr); 2 a file is
missing, not JSON, not a suite result, of another schema_version, the files have no point in
common, lack a role another has, or differ as machines and in settings without --force, a
single file is not of an MPI run of two ranks or more, or --plot names a directory that cannot
be written (one line on stderr says which).
)";

}  // namespace
}  // namespace compare_command

int cmd_compare(const std::vector<std::string>& args) {
    using namespace compare_command;
    CLI::App app{
        "suite compare: results of two or more runs (machines, builds) side by side, or the hosts of one MPI run"};
    app.footer(compare_examples);
    std::vector<std::string> paths;
    std::string format = compare_formats().all().front().name;
    bool force = false;
    std::string plot;
    app.add_option(
        "files", paths,
        "result files written by suite --out=FILE.json; the first is the reference (one file: an MPI run's hosts)");
    app.add_option("--format", format, compare_formats().described());
    app.add_flag("--force", force,
                 "compare files that differ both as machines and in build or settings, or lack a role another has");
    app.add_option("--plot", plot, "directory for the figures: each file's figures against footprint (PNG)");
    if (!parse_command_line(app, "suite compare", args)) return 0;
    const bool markdown = compare_formats().at(format).what;
    const std::string two_files =
        "compare needs at least two result files, e.g. ./suite compare a.json b.json, or one of an MPI run";
    const std::string see_help = " (see ./suite compare --help)";
    if (paths.empty()) throw UsageError(two_files + see_help);
    const DirPolicy plot_policy{.option = "--plot", .command = "suite compare", .inputs = identify_inputs(paths)};
    if (!plot.empty()) {
        if (paths.size() == 1) throw UsageError("--plot draws two or more result files side by side" + see_help);
        require_plotter("compare.py", "no --plot");
        OutputDir::check(plot, plot_policy);
    }
    if (paths.size() == 1) {
        // One file: the hosts (or ranks) of an MPI run side by side; a plain run has nothing to line up.
        const ResultFile run = load_result_file(paths[0]);
        if (!run.mpi) throw UsageError(two_files + "; " + paths[0] + " is a run of one process" + see_help);
        std::cout << render_host_comparison(run, markdown) << std::flush;
        return 0;
    }
    std::vector<ResultFile> files;
    for (const auto& p : paths) files.push_back(load_result_file(p));
    const std::string table = render_comparison(files, markdown, force);
    if (plot.empty()) {
        std::cout << table << std::flush;
        return 0;
    }
    CommandFrame frame("suite");
    OutputDir& dir = frame.claim_dir(plot, plot_policy);
    std::cout << table << std::flush;
    const Plotter p = find_plotter("compare.py");
    const std::string why = p.reason.empty() ? dir.with_writer([&](const std::string& at) {
        std::vector<std::string> args{at};
        args.insert(args.end(), paths.begin(), paths.end());
        return draw_with(p, args, at);
    })
                                             : p.reason;
    if (!why.empty()) std::cerr << "suite: error: --plot " << plot << ": no figures: " << why << "\n";
    return frame.finish(why.empty() ? 0 : 1, "the figures", true);
}

}  // namespace suite
