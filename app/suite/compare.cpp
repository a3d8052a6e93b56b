// `suite compare`: its options and help; the work is in harness/results/compare.cpp.
#include <iostream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "app/suite/commands.hpp"
#include "app/suite/parse.hpp"
#include "harness/results/compare.hpp"
#include "harness/results/compare_hosts.hpp"

namespace suite {
namespace compare_command {
namespace {

const char* const compare_examples = R"(
Points are matched by kernel, variant, pattern or ordering, size, threads, pinning, placement
and kernel parameters (--tol=... and the like). A point run on all of its machine's CPUs
(--threads=all) matches the other machines' all-CPU points whatever their core counts.
For each file: the best and median of the point's headline figure (GB/s for bandwidth kernels,
ns per load for latency, instructions for a deterministic run), and its ratio to the first file
as performance from the medians: above 1 is better than the first file, whichever way the
figure goes (for a bandwidth B/A, for a latency A/B), with a 95 % bootstrap interval of that
ratio from the repetitions. Then the geometric mean of those ratios per kernel. Before the
table: the context fields on which the files differ, each said to be of the machine (CPU,
sockets, NUMA nodes, cores, memory), of the build or settings (compiler and flags, build
type, the instruction set -march resolved to, THP, huge pages asked) or informational
(reported caches, governor). Files that differ in both machine and settings are refused (a
ratio could not say which made the difference) unless --force.

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
  ./suite compare cluster-mpi.json                                # one MPI run: its hosts side by side
  ./suite compare mpi-before.json mpi-after.json                  # two MPI runs, rank by rank

Exit status: 0 compared; 2 a file is missing, not JSON, not a suite result, of another
schema_version, have no point in common, or differ as machines and in settings without
--force, or a single file is not of an MPI run of two ranks or more (one line on stderr says
which).
)";

}  // namespace
}  // namespace compare_command

int cmd_compare(const std::vector<std::string>& args) {
    using namespace compare_command;
    CLI::App app{
        "suite compare: results of two or more runs (machines, builds) side by side, or the hosts of one MPI run"};
    app.footer(compare_examples);
    std::vector<std::string> paths;
    std::string format = "table";
    bool force = false;
    app.add_option(
        "files", paths,
        "result files written by suite --out=FILE.json; the first is the reference (one file: an MPI run's hosts)");
    app.add_option("--format", format, "table (default) | markdown");
    app.add_flag("--force", force, "compare files that differ both as machines and in build or settings");
    if (!parse_command_line(app, "suite compare", args)) return 0;
    if (format != "table" && format != "markdown")
        throw UsageError("unknown --format '" + format + "'; accepted: table, markdown");
    const std::string two_files =
        "compare needs at least two result files, e.g. ./suite compare a.json b.json, or one of an MPI run";
    const std::string see_help = " (see ./suite compare --help)";
    if (paths.empty()) throw UsageError(two_files + see_help);
    if (paths.size() == 1) {
        // One file: the hosts (or ranks) of an MPI run side by side; a plain run has nothing to line up.
        const ResultFile run = load_result_file(paths[0]);
        if (!run.mpi) throw UsageError(two_files + "; " + paths[0] + " is a run of one process" + see_help);
        std::cout << render_host_comparison(run, format == "markdown") << std::flush;
        return 0;
    }
    std::vector<ResultFile> files;
    for (const auto& p : paths) files.push_back(load_result_file(p));
    std::cout << render_comparison(files, format == "markdown", force) << std::flush;
    return 0;
}

}  // namespace suite
