#pragma once
// The runner measures one point of a sweep: pin the team, apply the memory policy, let the
// kernel set up (first touch), record where the pages went, warm up, time the repetitions,
// verify, summarise. It is the only code that reads the clock around a kernel.
#include <atomic>
#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "harness/kernel/kernel.hpp"
#include "harness/machine/placement.hpp"
#include "harness/machine/team.hpp"
#include "harness/machine/topology.hpp"
#include "harness/measure/instrument_set.hpp"
#include "harness/measure/result.hpp"

namespace suite {

struct Point {
    const KernelEntry* kernel = nullptr;
    Access access;
    std::string variant;
    std::uint64_t size = 0;
    int threads = 1;
    std::string mesh = "";  // kernels on a mesh: the --mesh spec, or "" (see KernelConfig::mesh)
    // The kernel's declared parameters (KernelConfig::params); one missing here runs at its default.
    Params params = {};
    SizeRole role = {};  // the default size's role; empty name for a size given
};

struct RunSettings {
    PinSpec pin;
    PlacementSpec placement;
    HugePages hugepages = HugePages::system;  // --hugepages: advice for every array of the point
    int reps = 0;                             // counted repetitions; 0: adaptive (>= min_time in total, >= min_reps)
    int min_reps = 5;
    double min_time_s = 0.2;
    // --fresh-arrays: each counted repetition after the first on the point's arrays allocated and
    // first-touched anew (the kernel set up again), then warmed with one uncounted batch. On this
    // VM a DRAM point's bandwidth follows where its pages landed, fixed for an allocation: its
    // repetitions agree while its median moves from run to run (docs/noise.md). Over fresh
    // arrays the median is over as many placements as repetitions.
    bool fresh_arrays = false;
    // Shorter kernel calls are batched so that a sample spans many clock ticks and the default
    // 0.2 s of repetitions stays at most ~200 samples (every one of them is written to the result).
    double min_sample_s = 1e-3;
    std::uint64_t seed = 1;
    const std::atomic<int>* stop = nullptr;  // set by a signal handler: abandon the point
    Instruments* instruments = nullptr;      // counters and energy; none: the clock only
    StabilityThresholds stability;           // when a point is flagged unstable
    // The ranks of an MPI run (suite-mpi), nullptr otherwise. With one, every rank runs the same
    // point at once: set-ups end together, the warm-up calls, batch and repetitions are the
    // most any rank wants (so each calls the kernel equally often: a distributed kernel
    // exchanges in every call), every sample starts when the last rank is ready, and a stop
    // raised on any rank stops them all at the same sample. The kernel gets it as KernelConfig::comm.
    const Comm* comm = nullptr;
};

// Thrown when RunSettings::stop is raised during a point; the point yields no record.
struct Interrupted : std::exception {
    const char* what() const noexcept override { return "interrupted"; }
};

Record run_point(const Point& point, const RunSettings& settings, const Topology& topo);

// The label of a point's callgrind dump, by which `suite deterministic` matches dumps to records.
std::string callgrind_label(const Record& r);

// Fills Record::rates from work, time statistics and threads.
Rates derive_rates(const Work& work, const TimeStats& time, Metric metric, int threads);

}  // namespace suite
