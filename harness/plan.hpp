#pragma once
// From the options of `suite run`, as given, to a Plan: every point of the sweep, validated
// completely (kernels, patterns, sizes, threads, pinning, placement, memory, output path)
// before anything runs or any file is written. Every problem is a UsageError.
#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "harness/cache_probe.hpp"
#include "harness/runner.hpp"
#include "harness/topology.hpp"

namespace suite {

struct RunOptions {
    std::string kernels;  // empty: the default sweep
    std::string patterns;
    std::string orderings;
    std::string mesh;    // --mesh: the mesh of kernels on a mesh
    std::string phases;  // --phase: the phases of kernels that have them (their variants)
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
    bool dry_run = false;  // print the points and stop
    std::string counters = "default";  // default | none | event names, comma separated
    std::string energy = "auto";       // auto | sysfs | perf | none
    double energy_baseline = 0;        // seconds of idle power measured before the sweep
    std::string hugepages = "system";  // thp | none | system (leave the system's setting)
    bool probe_caches = false;         // measure the caches first (cache_probe.hpp)
    MeasuredCaches measured;           // what the probe found; all 0: not measured
};

struct Plan {
    std::vector<Point> points;
    RunSettings settings;
    std::string out_path;
    std::string format;  // json | csv (for out_path), or what goes to stdout: table | json | csv
    bool quiet = false;
    bool dry_run = false;
    std::vector<std::string> notes;  // things the user should know before trusting the numbers
    Instruments instruments;         // RunSettings::instruments points here once the plan has its place
    nlohmann::json caches_measured;  // the probe's findings for context.caches_measured; null: no probe
};

Plan make_plan(const RunOptions& opts, const Topology& topo);

// The sizes used when none are given, for a team of `threads`: half an L1 data cache and half
// an L2 per thread, and a DRAM size of 16x the last level's total (so each array of a
// three-array kernel is at least 4x, with room for an index array), between 64 MiB and 1 GiB.
// Each cache is the reported one or, where a probe measured a smaller one, that.
std::vector<std::uint64_t> default_sizes(const Topology& topo, int threads, const MeasuredCaches& measured = {});

// The last-level cache (all instances) that a DRAM size must exceed: the reported one, or the
// measured one where it is smaller.
std::uint64_t effective_llc_bytes(const Topology& topo, std::uint64_t measured_llc_bytes);

}  // namespace suite
