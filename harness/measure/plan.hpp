#pragma once
// From the options of `suite run`, as given, to a Plan: every point of the sweep, validated
// completely (kernels, patterns, sizes, threads, pinning, placement, memory, output path)
// before anything runs or any file is written. Every problem is a UsageError.
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "harness/machine/topology.hpp"
#include "harness/measure/cache_probe.hpp"
#include "harness/measure/default_sizes.hpp"
#include "harness/measure/output_formats.hpp"
#include "harness/measure/runner.hpp"

namespace suite {

// One kernel of a sweep with the patterns or orderings it runs in (empty: its first).
struct SweepEntry {
    std::string kernel;
    std::vector<std::string> accesses;
};

struct RunOptions {
    std::string kernels;  // empty: default_sweep
    // What runs when no --kernel is given: the program's choice (the engine names no kernel).
    std::vector<SweepEntry> default_sweep;
    std::string patterns;
    std::string orderings;
    std::string mesh;        // --mesh: the mesh of kernels on a mesh
    std::string phases;      // --phase: the phases of kernels that have them (their variants)
    std::string strategies;  // --strategy: the strategies of kernels that have them (their variants)
    std::string particles;   // --particles: the particle orders of the MPM kernels (their variants)
    std::string isas;        // --isa: the instruction widths of peak-flops (its variants)
    // --NAME=X for a parameter a kernel declares (KernelInfo::params): NAME -> X as typed.
    std::map<std::string, std::string> params;
    std::string stores = "default";
    std::string size;
    std::string sizes;
    std::string threads;
    std::string pin = pin_name(PinMode::compact);
    std::string placement = placement_name(PlacementKind::local);
    int reps = -1;  // -1: adaptive
    double min_time = 0.2;
    bool fresh_arrays = false;  // --fresh-arrays
    std::uint64_t seed = 1;
    std::string out;
    std::string format;  // a name of output_formats(); "" = from --out's extension, table on the console
    bool quiet = false;
    bool dry_run = false;              // print the points and stop
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
    OutputFormat format = OutputFormat::table;  // of out_path, or of what goes to stdout
    bool quiet = false;
    bool dry_run = false;
    std::vector<std::string> notes;  // things the user should know before trusting the numbers
    Instruments instruments;         // RunSettings::instruments points here once the plan has its place
    nlohmann::json caches_measured;  // the probe's findings for context.caches_measured; null: no probe
};

// `open_energy` builds the energy instrument from --energy (the program's: RAPL for suite and
// suite-mpi); without one only --energy=auto|none is accepted, and energy is not measured.
Plan make_plan(const RunOptions& opts, const Topology& topo, const EnergyOpener& open_energy = {});

}  // namespace suite
