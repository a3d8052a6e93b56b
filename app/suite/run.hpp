#pragma once
// `suite run` (the default command): its options, and the sweep of a validated Plan with the
// console table, the result file and the signal handling around it.
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "app/suite/frame.hpp"
#include "harness/common/output_file.hpp"
#include "harness/machine/topology.hpp"
#include "harness/measure/plan.hpp"

namespace suite {

// The options of `suite run`, --NAME=X for every kernel parameter in the registry included.
void setup_run_options(CLI::App& app, RunOptions& opts);

// The kernels that take the parameter --NAME and its default: "default 0.05 (fem-cg, fem-spmv)",
// or each kernel with its own default where they differ.
std::string param_users(const std::string& name);

// The files a run reads (a --mesh=file:PATH), which its output must not be.
std::vector<FileIdentity> run_inputs(const RunOptions& opts);

// Runs the plan; returns the process exit status (0; 1 if a verification failed; 3 if a solver
// did not converge, which wins over 1; 128+signal). `frame` holds plan.out_path claimed (when the
// plan writes a file) and the stop a signal asks for: the sweep stops between points.
int execute_plan(Plan& plan, const Topology& topo, const std::vector<std::string>& argv, CommandFrame& frame);

}  // namespace suite
