#pragma once
// The sizes a sweep uses when none are given: one in each cache level and one in DRAM, from the
// caches hwloc reports or, where a probe measured a smaller one, the measured ones.
#include <cstdint>
#include <vector>

#include "harness/machine/topology.hpp"
#include "harness/measure/cache_probe.hpp"

namespace suite {

// The sizes used when none are given, for a team of `threads`: half an L1 data cache and half
// an L2 per thread, and a DRAM size of 16x the last level's total (so each array of a
// three-array kernel is at least 4x, with room for an index array), between 64 MiB and 1 GiB.
// Each cache is the reported one or, where a probe measured a smaller one, that.
std::vector<std::uint64_t> default_sizes(const Topology& topo, int threads, const MeasuredCaches& measured = {});

// The last-level cache (all instances) that a DRAM size must exceed: the reported one, or the
// measured one where it is smaller.
std::uint64_t effective_llc_bytes(const Topology& topo, std::uint64_t measured_llc_bytes);

}  // namespace suite
