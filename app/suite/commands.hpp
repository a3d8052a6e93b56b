#pragma once
// The subcommands of `suite`, one file each in app/suite/; main.cpp picks one by name. Each
// takes the arguments after its name and returns the process's exit status; bad usage is
// thrown as UsageError (exit 2). A command parses and wires: the work it asks for lives in
// harness/measure/ (running) or harness/results/ (reading and judging result files).
#include <string>
#include <vector>

namespace suite {

// `suite [run]`: measure kernels (run.cpp). `full_argv` is recorded in the result's context.
int cmd_run(const std::vector<std::string>& args, const std::vector<std::string>& full_argv);
// `suite list [--json] [--counters]`: kernels, patterns, placements; countable events (list.cpp).
int cmd_list(const std::vector<std::string>& args);
// `suite info [--json] [--probe]`: the machine as hwloc sees it, and what can be measured (info.cpp).
int cmd_info(const std::vector<std::string>& args);
// `suite compare A.json B.json ...` (compare.cpp).
int cmd_compare(const std::vector<std::string>& args);
// `suite check --baseline BASE.json RUN.json`: 0, 1 regressed (check.cpp).
int cmd_check(const std::vector<std::string>& args);
// `suite history add|list|steps|check|html`: runs across commits in SQLite (history.cpp); check: 0, 1 regressed.
int cmd_history(const std::vector<std::string>& args);
// `suite deterministic [run options]`: the run under valgrind's callgrind (deterministic.cpp);
// 0, 1 a kernel failed verification, 128+signal.
int cmd_deterministic(const std::vector<std::string>& args, const std::vector<std::string>& full_argv);
// `suite traverse --mesh=... --out=DIR`: how a loop walks a mesh, per ordering (traverse.cpp).
int cmd_traverse(const std::vector<std::string>& args);
// `suite matrix --mesh=... [--out=DIR]`: the fem matrix's structure, fill and SpMV per vertex ordering (matrix.cpp).
int cmd_matrix(const std::vector<std::string>& args);
// `suite mpm --case=dam-collapse --out=DIR`: the MPM dam collapse, particle snapshots and the front (mpm.cpp); 0, 1 a
// check failed.
int cmd_mpm(const std::vector<std::string>& args);
// `suite roofline [--threads=LIST] [--out=FILE] [--place=RESULT.json [--ceilings=FILE]]`: the
// machine's measured ceilings, and a run's points placed on them (roofline.cpp).
int cmd_roofline(const std::vector<std::string>& args, const std::vector<std::string>& full_argv);

}  // namespace suite
