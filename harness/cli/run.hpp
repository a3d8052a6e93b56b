#pragma once
// `suite run` (the default command): its options, and the sweep of a validated Plan with the
// console table, the result file and the signal handling around it.
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "harness/measure/plan.hpp"
#include "harness/machine/topology.hpp"

namespace suite {

void setup_run_options(CLI::App& app, RunOptions& opts);

// Runs the plan; returns the process exit status (0, 1 if a verification failed, 128+signal).
int execute_plan(Plan& plan, const Topology& topo, const std::vector<std::string>& argv);

}  // namespace suite
