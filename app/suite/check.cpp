// `suite check`: its options and help; the work is in harness/results/check.cpp.
#include <iostream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "app/suite/commands.hpp"
#include "app/suite/parse.hpp"
#include "harness/common/output_file.hpp"
#include "harness/results/check.hpp"

namespace suite {
namespace check_command {
namespace {

const char* const check_examples = R"(
Each figure has a direction: bandwidth higher is better; latency, hardware counters per
element, energy per call and callgrind counts lower is better. For each figure of each point
found in both files:
  unchanged     the medians differ by less than the tolerance (the smallest effect that counts);
  regressed /   they differ by more, and the repetitions tell the runs apart: a one-sided
  improved      Mann-Whitney U test on the two runs' repetitions gives p < alpha;
  inconclusive  they differ by more, but the repetitions cannot tell (with 5 against 5 the
                smallest p is 1/252; with 3 against 3 it is 1/20, never below 0.01), or
                either file flagged the point unstable (the machine was busy). Never gated.
Counters and energy keep no repetitions: they regress beyond tolerance + the combined spread
(a quarter of each min..max range). A count of fewer than 100 events a repetition in both runs
is not gated by ratio. Callgrind counts are exact (spread 0). The change is printed signed,
with a 95 % bootstrap interval of the ratio of medians where there are repetitions.
A point that fails verification in the run is a regression. Points only in one file are listed,
not gated. The files must come from the same machine and build: a difference in CPU, cores,
memory, compiler, flags, instruction set, build type or huge pages is refused (exit 2, naming the fields)
unless --force.
MPI runs (suite-mpi): each rank's records and the aggregate of all ranks are points of their own,
matched rank with rank and aggregate with aggregate, so a slow rank fails the gate even where the
aggregate (which waits for the slowest rank) hardly moved; its row names the rank and its host.
A plain baseline gates only the aggregate of a run of one rank; against a run of more ranks
nothing is in common (exit 2, saying how many processes each ran).

Examples:
  ./suite check --baseline results/baseline/ci.json run.json
  ./suite check --baseline results/baseline/ci.json run.json --tolerance=25% --markdown=gate.md
  ./suite check --baseline base.json run.json --alpha=0.05        # a weaker test, more alarms
  ./suite check --baseline results/baseline/ci-deterministic.json det.json --tolerance=1%
  ./suite check --baseline mpi-base.json mpi-run.json --tolerance=25%   # every rank and the aggregate

Exit status: 0 nothing regressed; 1 something regressed (listed, with the improvements and the
inconclusive figures); 2 the input cannot be used (missing, not JSON, not a suite result,
interrupted, nothing in common with the baseline, another machine or build), one line on stderr.
)";

}  // namespace
}  // namespace check_command

int cmd_check(const std::vector<std::string>& args) {
    using namespace check_command;
    CLI::App app{"suite check: the CI regression gate, a run against a baseline"};
    app.footer(check_examples);
    std::string baseline_path, tolerance = "10%", alpha = "0.01", markdown;
    bool force = false;
    std::vector<std::string> runs;
    app.add_option("--baseline", baseline_path, "the result file to compare against (e.g. results/baseline/ci.json)");
    app.add_option("run", runs, "the result file of the run to gate");
    app.add_option("--tolerance", tolerance, "the smallest change that counts, in percent (default 10%)");
    app.add_option("--alpha", alpha, "significance level of the one-sided test on the repetitions (default 0.01)");
    app.add_flag("--force", force,
                 "compare even when the files come from different machines or builds (the differences are listed)");
    app.add_option("--markdown", markdown, "also write a Markdown summary to FILE (for a CI comment)");
    if (!parse_command_line(app, "suite check", args)) return 0;
    if (baseline_path.empty())
        throw UsageError(
            "check needs --baseline=FILE, e.g. ./suite check --baseline results/baseline/ci.json run.json");
    if (runs.size() != 1)
        throw UsageError(
            "check needs exactly one run file after the options, e.g. ./suite check --baseline base.json run.json");
    GateRule rule;
    rule.tolerance = parse_tolerance(tolerance);
    rule.alpha = parse_alpha(alpha);
    // Claimed before anything is read or written: never a device, never one of the inputs.
    OutputFile md;
    if (!markdown.empty()) md = OutputFile::claim(markdown, "--markdown", identify_inputs({baseline_path, runs[0]}));
    const ResultFile base = load_result_file(baseline_path);
    const ResultFile run = load_result_file(runs[0]);
    for (const ResultFile* f : {&base, &run})
        if (!f->complete)
            throw InputError(f->path + ": the run was interrupted (\"complete\": false); gate only complete runs");
    CheckReport rep = check_run(base, run, rule, force);
    for (const auto* f : {&base, &run}) rep.notes.insert(rep.notes.end(), f->notes.begin(), f->notes.end());
    if (md.claimed()) {
        // Exit status 1 means "regressed" here; a summary that cannot be written is not that.
        try {
            md.write(render_check_markdown(rep));
        } catch (const std::exception& e) {
            throw UsageError(e.what());
        }
    }
    std::cout << render_check_text(rep) << std::flush;
    return rep.count(Verdict::regressed) ? 1 : 0;
}

}  // namespace suite
