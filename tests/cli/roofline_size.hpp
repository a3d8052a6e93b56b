#pragma once
// A small memory footprint for `suite roofline --dram-size` in tests: 48 MiB, or more where the
// last-level cache holds that much (the roofline refuses a memory footprint the caches hold).
#include <algorithm>
#include <cstdint>
#include <string>

#include "harness/machine/topology.hpp"

namespace suite::test {

inline std::uint64_t roofline_test_dram_bytes() {
    const std::uint64_t llc = suite::Topology::load().last_level_cache_total_bytes();
    return std::max<std::uint64_t>(48ULL << 20, (2 * llc + (1ULL << 20) - 1) >> 20 << 20);
}

inline std::string roofline_test_dram_size() {
    return "--dram-size=" + std::to_string(roofline_test_dram_bytes() >> 20) + "MiB";
}

}  // namespace suite::test
