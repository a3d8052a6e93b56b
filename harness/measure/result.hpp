#pragma once
// One measured point, as a plain struct. The runner fills it; reporters only render it.
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "harness/common/stats.hpp"
#include "harness/common/units.hpp"
#include "harness/instruments/machine_load.hpp"
#include "harness/instruments/measurements.hpp"
#include "harness/kernel/kernel.hpp"
#include "harness/machine/placement.hpp"
#include "harness/machine/team.hpp"

namespace suite {

// Rates derived from Work and the time statistics, in one place (derive_rates in runner.cpp).
struct Rates {
    // Metric::bandwidth: GB/s with 1 GB = 1e9 B, from the best (minimum) and the median time.
    std::optional<double> stream_gbps_best, stream_gbps_median;
    std::optional<double> hardware_gbps_best, hardware_gbps_median;
    // Metric::latency: nanoseconds per dependent load of one thread.
    std::optional<double> ns_per_load_best, ns_per_load_median;
    double units_per_second_best = 0;
    std::optional<double> gflops_best;
};

// Where a record of an MPI run (suite-mpi) comes from: one rank's own measurement, or the
// aggregate of all ranks' (per repetition the slowest rank's time, the work of all together).
// Scope::none in a run of one process, and then absent from the JSON.
struct RankScope {
    enum class Kind { none, rank, aggregate } kind = Kind::none;
    int ranks = 0;          // in the run
    int rank = -1;          // Kind::rank
    std::string host;       // Kind::rank: the rank's host
    int hosts = 0;          // Kind::aggregate: distinct hosts
    int slowest_rank = -1;  // Kind::aggregate: the rank with the longest best time
    std::string slowest_host;
    double spread = 0;  // Kind::aggregate: slowest rank's best time / fastest rank's (>= 1)
};

// What a default size stands for. Empty `name`: a size the user gave, which stands for itself.
struct SizeRole {
    std::string name;               // "L1/2", "L2/2", "L3/2", "DRAM"
    std::string cache;              // the cache it was sized from: "L1", "L2", or the last level ("L3")
    std::uint64_t cache_bytes = 0;  // that cache: one instance for L1/L2, all instances of the last level
    std::string source;             // "measured" (the probe), "reported" (hwloc), "assumed" (none known)
};

struct Record {
    std::string kernel;
    std::string variant;  // "" or "nt", a phase or a strategy
    std::string name;     // kernel plus variant, e.g. "copy-nt": the name reports use
    AccessAxis axis = AccessAxis::pattern;
    std::string access;  // "sequential", "random", "strided:8", "morton", ...
    SizeKind size_kind = SizeKind::bytes;
    std::uint64_t size_requested = 0;
    SizeRole size_role;  // the cache the default size came from; empty name: the size was given
    // The smallest array over all last-level cache instances together: a DRAM figure wants >= 4.
    std::optional<double> smallest_array_over_llc;
    Work work;  // per repetition
    std::string unit;
    Metric metric = Metric::bandwidth;
    int threads = 1;
    std::string pin;
    std::vector<ThreadBinding> bindings;
    bool binding_held = false;  // every thread still had its CPU set after the timed repetitions
    std::string placement;      // as asked
    int placement_node = -1;    // node chosen for node:N / remote
    std::vector<int> interleave_nodes;
    std::vector<ArrayPlacement> pages;  // as observed after first touch
    std::string hugepages = "system";   // --hugepages as asked: system, thp or none
    int repetitions = 0;                // counted ones, after the warm-up
    int warmup = 0;                     // uncounted calls before the repetitions (the runner sets it)
    int batch = 1;                      // kernel calls per timed sample (tiny sizes); times are per call
    bool fresh_arrays = false;          // --fresh-arrays: each counted repetition on arrays set up anew
    std::vector<double> samples_s;      // per call, one per counted repetition
    TimeStats time;
    Rates rates;
    Verification verification;
    CounterReadings counters;  // around the same repetitions as samples_s
    EnergyReadings energy;
    Stability stability;  // what else the machine did around the repetitions; unstable: a noisy point
    std::uint64_t seed = 0;
    std::string mesh;         // the --mesh spec of a kernel on a mesh; "" otherwise
    Params params;            // the kernel's declared parameters, as it ran (KernelConfig::params)
    std::vector<Fact> facts;  // what the kernel reported about its last run (Kernel::facts)
    RankScope mpi;            // the rank it came from in an MPI run; Kind::none otherwise
};

// A size as people read it: "64MiB" for a footprint, "1000000" for a count.
inline std::string size_label(SizeKind kind, std::uint64_t size) {
    return kind == SizeKind::bytes ? format_bytes(size) : std::to_string(size);
}

inline std::string display_name(const std::string& kernel, const std::string& variant) {
    return variant.empty() ? kernel : kernel + "-" + variant;
}

}  // namespace suite
