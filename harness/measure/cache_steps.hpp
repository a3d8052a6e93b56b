#pragma once
// Finding the steps of a cost-versus-footprint curve (ns per dependent load, or ns per byte)
// that a cache hierarchy draws: flat plateaus, one per level, joined by rises. A pure function
// of the points, so that it can be tested on synthetic curves; it never measures anything.
#include <cstdint>
#include <optional>
#include <vector>

namespace suite {

struct CurvePoint {
    std::uint64_t size_bytes = 0;
    double value = 0;  // a cost that grows with the level: ns per load, ns per byte
};

struct Plateau {
    std::size_t first = 0, last = 0;  // indexes of its first and last point in the sorted curve
    double value = 0;                 // the median of its points
};

struct StepOptions {
    // A point more than this factor away from the median of the plateau being built starts a
    // new segment.
    double jump = 1.25;
    // Segments shorter than this many points are rises between levels (or noise), not levels.
    std::size_t min_points = 3;
    // A point is in the middle of a rise when the curve climbs more than sqrt(jump) both over
    // the `rise_span` points before it and over those after it (2: half an octave each side at
    // four points an octave); such a point joins no plateau. The last point of a plateau before
    // a sharp step climbs on one side only, so it stays.
    std::size_t rise_span = 2;
    // The tail: from the first point at or above `ceiling` after which most points (80 %) stay
    // there, everything is one plateau, however noisy (memory on a shared machine varies by
    // tens of per cent). Or from the first point of at least `tail_from_size` bytes.
    std::optional<double> ceiling;
    std::optional<std::uint64_t> tail_from_size;
    // Neighbouring plateaus closer than this factor are one level (a rise inside a level, e.g.
    // TLB misses, or noise that split one).
    double min_step = 1.5;
    // The capacity of a level: the footprint at which the curve has risen this fraction of the
    // way, on a logarithmic scale, from the level's plateau to the next one (so the first rise
    // ends it, not the bulk of the step). Its reach: the same fraction on a linear scale, where
    // a fifth of the extra cost of the next level shows; with a sharp step the two agree.
    double crossing = 0.2;
};

struct Steps {
    std::vector<CurvePoint> curve;          // the points sorted by size, smoothed (running median of 3)
    std::vector<Plateau> plateaus;          // in order of size, each costlier than the one before
    std::vector<std::uint64_t> capacities;  // capacities[k]: where plateau k ends (plateaus.size() - 1 of them)
    std::vector<std::uint64_t> reaches;     // reaches[k]: where the curve is a fifth of the way to plateau k + 1
    bool tail = false;                      // the last plateau is the tail (StepOptions::ceiling)
};

// The plateaus of `points` (any order) and the capacities between them. Fewer than
// `min_points` points give no plateau.
Steps find_steps(std::vector<CurvePoint> points, const StepOptions& options = {});

// A latency curve read as a cache hierarchy: every plateau below `memory_ns` is a cache level,
// the first one at or above it (and all that follows) is memory. `steps` should come from
// find_steps with ceiling = memory_ns (latency_step_options()).
struct MeasuredLevel {
    int level = 0;                                // 1 for the first plateau, ...
    std::optional<std::uint64_t> capacity_bytes;  // unset when the sweep ended on this level
    double latency_ns = 0;
    // A level without a plateau of its own: between the last plateau and memory the curve
    // lingers (a shared last-level cache that neighbours keep evicting) well past the
    // plateau's capacity (half an octave or more) before memory latency dominates. Its
    // capacity is that reach, its latency the median of the points in between.
    bool partial = false;
};
struct Hierarchy {
    std::vector<MeasuredLevel> levels;
    std::optional<double> memory_latency_ns;   // unset when the sweep never reached memory
    std::optional<std::uint64_t> memory_from;  // the smallest size of the memory plateau
};
// No cache has a latency this long, and no memory a shorter one (a dependent load from DRAM
// takes 70 ns and more; the slowest last-level caches, on large meshes, about 40).
constexpr double memory_latency_floor_ns = 60;
StepOptions latency_step_options();
Hierarchy read_hierarchy(const Steps& latency_steps, double memory_ns = memory_latency_floor_ns);

}  // namespace suite
