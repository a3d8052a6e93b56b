// `suite check`: its options and help; the work is in harness/results/check.cpp.
#include <iostream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "harness/cli/commands.hpp"
#include "harness/cli/parse.hpp"
#include "harness/common/output_file.hpp"
#include "harness/results/check.hpp"

namespace suite {

namespace {

const char* const check_examples = R"(
Each figure has a direction: bandwidth higher is better; latency, hardware counters per
element, energy per call and callgrind counts lower is better. A figure regresses when the
run's median is worse than the baseline's by more than
    tolerance + sqrt(spread_baseline^2 + spread_run^2),
where a run's spread is the robust relative standard deviation of its repetitions
(1.4826 * MAD / median of the time samples; a quarter of the min..max range for counters and
energy; 0 for callgrind counts, which are exact). It improves when it is better by as much.
A point that fails verification in the run is a regression. Points only in one file are listed,
not gated; a run with none of the baseline's points cannot be gated (exit 2).

Examples:
  ./suite check --baseline results/baseline/ci.json run.json
  ./suite check --baseline results/baseline/ci.json run.json --tolerance=25% --markdown=gate.md
  ./suite check --baseline results/baseline/ci-deterministic.json det.json --tolerance=1%

Exit status: 0 nothing regressed; 1 something regressed (listed, with the improvements);
2 the input cannot be used (missing, not JSON, not a suite result, interrupted, nothing in
common with the baseline), one line on stderr.
)";

}  // namespace

int cmd_check(const std::vector<std::string>& args) {
    CLI::App app{"suite check: the CI regression gate, a run against a baseline"};
    app.footer(check_examples);
    std::string baseline_path, tolerance = "10%", markdown;
    std::vector<std::string> runs;
    app.add_option("--baseline", baseline_path, "the result file to compare against (e.g. results/baseline/ci.json)");
    app.add_option("run", runs, "the result file of the run to gate");
    app.add_option("--tolerance", tolerance, "allowed worsening beyond the runs' spread, in percent (default 10%)");
    app.add_option("--markdown", markdown, "also write a Markdown summary to FILE (for a CI comment)");
    if (!parse_command_line(app, "suite check", args)) return 0;
    if (baseline_path.empty()) throw UsageError("check needs --baseline=FILE, e.g. ./suite check --baseline results/baseline/ci.json run.json");
    if (runs.size() != 1) throw UsageError("check needs exactly one run file after the options, e.g. ./suite check --baseline base.json run.json");
    const double tol = parse_tolerance(tolerance);
    // Claimed before anything is read or written: never a device, never one of the inputs.
    OutputFile md;
    if (!markdown.empty()) md = OutputFile::claim(markdown, "--markdown", identify_inputs({baseline_path, runs[0]}));
    const ResultFile base = load_result_file(baseline_path);
    const ResultFile run = load_result_file(runs[0]);
    for (const ResultFile* f : {&base, &run})
        if (!f->complete) throw InputError(f->path + ": the run was interrupted (\"complete\": false); gate only complete runs");
    CheckReport rep = check_run(base, run, tol);
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
