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
and kernel parameters (--tol=... and the like).
For each file: the best and median of the point's headline figure (GB/s for bandwidth kernels,
ns per load for latency, instructions for a deterministic run), and its ratio to the first file
as performance: above 1 is better than the first file, whichever way the figure goes (for a
bandwidth B/A, for a latency A/B). Then the geometric mean of those ratios per kernel. Before
the table: the context fields on which the files differ (CPU, sockets, NUMA nodes, caches,
memory, compiler and flags, instruction set, THP, governor).

Examples:
  ./suite compare results/epyc.json results/xeon.json          # two machines
  ./suite compare before.json after.json --format=markdown > comparison.md
  ./suite compare tests/fixtures/results/vm-native.json tests/fixtures/results/vm-x86-64-v3.json

Exit status: 0 compared; 2 a file is missing, not JSON, not a suite result, of another
schema_version, or the files have no point in common (one line on stderr says which).
)";

}  // namespace

int cmd_compare(const std::vector<std::string>& args) {
    CLI::App app{"suite compare: results of two or more runs (machines, builds) side by side"};
    app.footer(compare_examples);
    std::vector<std::string> paths;
    std::string format = "table";
    app.add_option("files", paths, "result files written by suite --out=FILE.json; the first is the reference");
    app.add_option("--format", format, "table (default) | markdown");
    if (!parse_command_line(app, "suite compare", args)) return 0;
    if (format != "table" && format != "markdown") throw UsageError("unknown --format '" + format + "'; accepted: table, markdown");
    if (paths.size() < 2)
        throw UsageError("compare needs at least two result files, e.g. ./suite compare a.json b.json (see ./suite compare --help)");
    std::vector<ResultFile> files;
    for (const auto& p : paths) files.push_back(load_result_file(p));
    std::cout << render_comparison(files, format == "markdown") << std::flush;
    return 0;
}

}  // namespace suite
