#pragma once
// The sizes a sweep uses when none are given: one in each cache level and one in DRAM, from the
// caches hwloc reports or, where a probe measured a smaller one, the measured ones. Each carries
// its role (which cache it was sized from), so that machines with other caches can be compared
// level by level.
#include <cstdint>
#include <string>
#include <vector>

#include "harness/machine/topology.hpp"
#include "harness/measure/cache_probe.hpp"
#include "harness/measure/result.hpp"

namespace suite {

struct DefaultSize {
    std::uint64_t bytes = 0;
    SizeRole role;
};

// The sizes used when none are given, for a team of `threads`: half an L1 data cache and half
// an L2 per thread; where the probe measured the last level (L3 or beyond), half of it for the
// whole team when that exceeds the L2 size; and a DRAM size of 16x the last level's total (so
// each array of a three-array kernel is at least 4x, with room for an index array), between
// 64 MiB and 1 GiB. Each cache is the reported one or, where a probe measured a smaller one, that.
std::vector<DefaultSize> default_points(const Topology& topo, int threads, const MeasuredCaches& measured = {});

// The bytes of default_points, in order.
std::vector<std::uint64_t> default_sizes(const Topology& topo, int threads, const MeasuredCaches& measured = {});

// The last-level cache (all instances) that a DRAM size must exceed: the reported one, or the
// measured one where it is smaller.
std::uint64_t effective_llc_bytes(const Topology& topo, std::uint64_t measured_llc_bytes);

}  // namespace suite
