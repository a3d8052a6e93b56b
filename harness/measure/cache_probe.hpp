#pragma once
// The caches this process really gets, measured rather than reported: the latency kernel's
// pointer chase and the load kernel's bandwidth, one pinned thread, at footprints from 4 KiB up
// in quarter-octave steps, each point run through the runner (verified like any other), and the
// curves read with find_steps. VMs and some CPUs report caches a program does not get (the
// development VM: 32 MiB of L3 reported, memory latency from about 3-6 MB on). It takes seconds,
// so nothing probes unless asked: `suite info --probe`, `suite run --probe-caches`.
#include <atomic>
#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "harness/machine/placement.hpp"
#include "harness/machine/topology.hpp"
#include "harness/measure/cache_steps.hpp"

namespace suite {

// What a probe measured, as far as the default sizes care: one instance of L1 and of L2, and
// the last level over all its instances; 0 where it measured nothing.
struct MeasuredCaches {
    std::uint64_t l1 = 0, l2 = 0, llc_total = 0;
};

struct ProbeOptions {
    // Largest footprint; 0: 4x the reported last-level cache (all instances), between 16 MiB and
    // 512 MiB. The sweep stops earlier once one octave and a half of points lie at memory latency.
    std::uint64_t max_bytes = 0;
    int points_per_octave = 4;
    bool bandwidth = true;  // also the load kernel's bandwidth at the same sizes
    HugePages hugepages = HugePages::system;
    const std::atomic<int>* stop = nullptr;  // as RunSettings::stop
    // The kernels it runs, the program's choice: a dependent-load chase whose record has
    // ns_per_load, and a read-only stream whose record has stream GB/s. Both must be given.
    std::string latency_kernel, latency_pattern;
    std::string bandwidth_kernel, bandwidth_pattern;
};

struct CacheProbe {
    std::vector<CurvePoint> latency_ns;      // best ns per dependent load at each footprint
    std::vector<CurvePoint> bandwidth_gbps;  // best GB/s of the load kernel at each footprint
    Steps latency_steps;
    Hierarchy hierarchy;                         // read from latency_steps
    std::vector<std::uint64_t> bandwidth_steps;  // where the bandwidth curve steps down
    int cpu = -1;                                // the CPU the thread was pinned to (-1: not pinned)
    std::string hugepages = "system";
    double seconds = 0;
};

// Measures. Throws what the runner throws (Interrupted when `stop` is raised).
CacheProbe probe_caches(const Topology& topo, const ProbeOptions& options);

// The last cache level the probe found, over all its instances (the capacity one thread sees
// times the instances hwloc reports for that level), when the sweep went on into memory; 0
// when it did not find one.
std::uint64_t measured_llc_total(const CacheProbe& probe, const Topology& topo);

// L1 and L2 as measured (levels with a plateau of their own and a capacity) and
// measured_llc_total().
MeasuredCaches measured_caches(const CacheProbe& probe, const Topology& topo);

// context.caches_measured of a result, and `suite info --probe --json`'s "caches_measured".
nlohmann::json to_json(const CacheProbe& probe, const Topology& topo);

// The measured levels beside the reported ones, for the console.
std::string format_probe(const CacheProbe& probe, const Topology& topo);

}  // namespace suite
