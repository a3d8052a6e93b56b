#pragma once
// This machine's roofline, measured: the compute ceiling (a peak kernel at each instruction width)
// and a bandwidth ceiling per memory level (the best of the ceiling kernels the program names,
// those that bypass the caches in memory only, at a footprint inside the level), per thread
// count, each point run through the runner and verified like any other. `suite roofline` runs it
// and writes it (roofline.cpp in app/suite); harness/results/roofline_place.hpp reads it back
// and places the points of a run on it.
//
// Levels: the caches the cache probe measures (capacity as one thread sees it, one instance)
// where it ran, else the ones hwloc reports; then memory. The footprint of a level's ceiling
// at t threads pinned compact is half of what the level holds for them, `level_bytes`; a level
// whose half does not exceed what the level below holds for them has no footprint of its own
// at that thread count, and is measured at none (said in its `reason`).
#include <atomic>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "harness/machine/placement.hpp"
#include "harness/machine/team.hpp"
#include "harness/machine/topology.hpp"
#include "harness/measure/cache_probe.hpp"

namespace suite {

struct RooflineLevel {
    std::string name;                  // "L1", "L2", "L3", "DRAM"
    std::uint64_t capacity_bytes = 0;  // one instance; 0 for DRAM
    int instances = 1;                 // how many the machine has
    int pus_per_instance = 1;          // how many PUs share one
    std::string source;                // "measured" (the probe), "reported" (hwloc), "memory"
};

// What the level holds for t threads pinned compact: one instance per pus_per_instance threads
// (at most all of them) times its capacity; 0 for DRAM, which holds everything.
std::uint64_t level_bytes(const RooflineLevel& level, int threads);

struct BandwidthFigure {
    std::string kernel;  // the record's name: "copy-nt"
    double gbps = 0;     // STREAM-convention bytes, best repetition
    double hardware_gbps = 0;
};

struct LevelCeiling {
    std::string level;
    std::uint64_t footprint_bytes = 0;  // 0: not measured at this thread count (reason says why)
    std::string reason;
    std::optional<BandwidthFigure> read_only, read_write;  // the best of each kind
    std::vector<BandwidthFigure> measured;                 // every kernel run here
    // The ceiling: the best STREAM GB/s of any kernel, and the best hardware estimate.
    double gbps() const;
    double hardware_gbps() const;
    std::string best_kernel() const;
};

struct PeakFigure {
    std::string isa, kernel;  // "avx512", "peak-flops-avx512"
    double gflops = 0;
};

struct ThreadCeilings {
    int threads = 1;
    std::vector<PeakFigure> peak;         // one per width, narrowest first
    std::vector<LevelCeiling> bandwidth;  // one per level, in order
    double peak_gflops() const;           // the best of `peak`
    const LevelCeiling* level(const std::string& name) const;
};

struct Roofline {
    std::vector<RooflineLevel> levels;     // caches in order, DRAM last
    std::vector<ThreadCeilings> ceilings;  // one per thread count, as asked
    nlohmann::json caches_measured;        // the probe's findings (null: no probe)
    double seconds = 0;
    bool complete = true;  // false: interrupted; what was measured is kept
};

// A kernel a level's ceiling is the best of. `memory_only`: it can win only in memory (stores
// that bypass the caches), so it runs at the DRAM footprint alone.
struct CeilingKernel {
    std::string kernel, variant;
    bool read_only = false;
    bool memory_only = false;
};

struct RooflineOptions {
    // The kernels, the program's choice: the bandwidth ceiling's, and the compute ceiling's
    // (one point per variant, each an instruction width, at its default count).
    std::vector<CeilingKernel> ceiling_kernels;
    std::string peak_kernel;
    ProbeOptions probe_options;  // its kernels; stop is taken from here
    std::vector<int> threads = {1};
    PinSpec pin;                                       // compact, normally
    double min_time_s = 0.2;                           // per point
    bool probe = true;                                 // measure the caches first; else use the reported ones
    std::uint64_t dram_bytes = 0;                      // 0: the default sweep's DRAM size for each thread count
    const std::atomic<int>* stop = nullptr;            // raised: stop at the next point, complete = false
    std::function<void(const std::string&)> progress;  // one line per point measured
};

// The levels a roofline measures (the probe's, when given, else hwloc's), DRAM last.
std::vector<RooflineLevel> roofline_levels(const Topology& topo, const CacheProbe* probe);

Roofline measure_roofline(const Topology& topo, const RooflineOptions& options);

// The "levels", "ceilings", "seconds" and "complete" of a roofline file (the caller adds the
// kind, schema version, context and fingerprint).
nlohmann::json to_json(const Roofline& roofline);

}  // namespace suite
