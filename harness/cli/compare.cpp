// `suite compare`: its options and help; the work is in harness/results/compare.cpp.
#include <iostream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "harness/cli/commands.hpp"
#include "harness/cli/parse.hpp"
#include "harness/results/compare.hpp"

namespace suite {

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

Examples:
  ./suite compare results/epyc.json results/xeon.json          # two machines
  ./suite compare before.json after.json --format=markdown > comparison.md
  ./suite compare tests/fixtures/results/vm-native.json tests/fixtures/results/vm-x86-64-v3.json
  ./suite compare epyc-thp.json xeon-nothp.json --force          # both changed: listed, compared anyway

Exit status: 0 compared; 2 a file is missing, not JSON, not a suite result, of another
schema_version, have no point in common, or differ as machines and in settings without
--force (one line on stderr says which).
)";

}  // namespace

int cmd_compare(const std::vector<std::string>& args) {
    CLI::App app{"suite compare: results of two or more runs (machines, builds) side by side"};
    app.footer(compare_examples);
    std::vector<std::string> paths;
    std::string format = "table";
    bool force = false;
    app.add_option("files", paths, "result files written by suite --out=FILE.json; the first is the reference");
    app.add_option("--format", format, "table (default) | markdown");
    app.add_flag("--force", force, "compare files that differ both as machines and in build or settings");
    if (!parse_command_line(app, "suite compare", args)) return 0;
    if (format != "table" && format != "markdown") throw UsageError("unknown --format '" + format + "'; accepted: table, markdown");
    if (paths.size() < 2)
        throw UsageError("compare needs at least two result files, e.g. ./suite compare a.json b.json (see ./suite compare --help)");
    std::vector<ResultFile> files;
    for (const auto& p : paths) files.push_back(load_result_file(p));
    std::cout << render_comparison(files, format == "markdown", force) << std::flush;
    return 0;
}

}  // namespace suite
