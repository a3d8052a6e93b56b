#include "harness/measure/default_sizes.hpp"

#include <algorithm>

namespace suite {

std::uint64_t effective_llc_bytes(const Topology& topo, std::uint64_t measured) {
    const std::uint64_t reported = topo.last_level_cache_total_bytes();
    if (measured == 0) return reported;
    return reported == 0 ? measured : std::min(reported, measured);
}

std::vector<std::uint64_t> default_sizes(const Topology& topo, int threads, const MeasuredCaches& measured) {
    // The smaller of the reported and the measured size of one instance of `level`, or `fallback`.
    auto cache = [&](int level, std::uint64_t m, std::uint64_t fallback) {
        const Cache* c = topo.find_cache(level);
        const std::uint64_t reported = c ? c->size_bytes : 0;
        if (reported == 0) return m ? m : fallback;
        return m ? std::min(reported, m) : reported;
    };
    const auto t = static_cast<std::uint64_t>(threads);
    // Half a cache per thread, in whole cache lines.
    const std::uint64_t small = t * (cache(1, measured.l1, 32ULL << 10) / 2 / 64 * 64);
    const std::uint64_t medium = t * (cache(2, measured.l2, 1ULL << 20) / 2 / 64 * 64);
    const std::uint64_t measured_llc_bytes = measured.llc_total;
    // Capped at 1 GiB so the default sweep stays short where a VM reports a huge LLC that it
    // does not really give; each result records how its arrays compare with the LLC.
    // Whole MiB, so that a measured last level does not give an odd-looking size.
    const std::uint64_t mib = 1ULL << 20;
    const std::uint64_t sixteen_llc = (16 * effective_llc_bytes(topo, measured_llc_bytes) + mib - 1) / mib * mib;
    const std::uint64_t dram = std::clamp<std::uint64_t>(sixteen_llc, 64 * mib, 1ULL << 30);
    return {small, medium, dram};
}

}  // namespace suite
