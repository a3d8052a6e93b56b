#pragma once
// `suite run` (the default command): its options as given, their validation into a Plan, and
// the sweep. Validation happens completely before anything runs or any file is written.
#include <cstdint>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "harness/runner.hpp"
#include "harness/topology.hpp"

namespace suite {

struct RunOptions {
    std::string kernels;  // empty: the default sweep
    std::string patterns;
    std::string orderings;
    std::string stores = "default";
    std::string size;
    std::string sizes;
    std::string threads;
    std::string pin = "compact";
    std::string placement = "local";
    int reps = -1;  // -1: adaptive
    double min_time = 0.2;
    std::uint64_t seed = 1;
    std::string out;
    std::string format;  // table | json | csv; "" = from --out's extension, table on the console
    bool quiet = false;
    bool dry_run = false;
};

struct Plan {
    std::vector<Point> points;
    RunSettings settings;
    std::string out_path;
    std::string format;  // json | csv (for out_path), and what goes to stdout
    bool quiet = false;
    bool dry_run = false;  // print the points and stop
};

void setup_run_options(CLI::App& app, RunOptions& opts);

// Throws UsageError naming the first problem.
Plan make_plan(const RunOptions& opts, const Topology& topo);

// Runs the plan; returns the process exit status (0, 1 if a verification failed, 128+signal).
int execute_plan(Plan& plan, const Topology& topo, const std::vector<std::string>& argv);

// The sizes used when none are given: one in L1, one in L2, one DRAM-sized (every array of a
// three-array kernel at least 4x the last-level cache, between 64 MiB and 1 GiB).
std::vector<std::uint64_t> default_sizes(const Topology& topo);

}  // namespace suite
