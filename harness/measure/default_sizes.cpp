#include "harness/measure/default_sizes.hpp"

#include <algorithm>

namespace suite {

std::uint64_t effective_llc_bytes(const Topology& topo, std::uint64_t measured) {
    const std::uint64_t reported = topo.last_level_cache_total_bytes();
    if (measured == 0) return reported;
    return reported == 0 ? measured : std::min(reported, measured);
}

namespace {

// The cache a size is taken from: the smaller of the reported and the measured one, or `fallback`.
SizeRole cache_role(const Topology& topo, int level, std::uint64_t measured, std::uint64_t fallback) {
    const Cache* c = topo.find_cache(level);
    const std::uint64_t reported = c ? c->size_bytes : 0;
    SizeRole role{"L" + std::to_string(level) + "/2", "L" + std::to_string(level), 0, ""};
    if (reported == 0 && measured == 0)
        role.cache_bytes = fallback, role.source = "assumed";
    else if (measured && (reported == 0 || measured < reported))
        role.cache_bytes = measured, role.source = "measured";
    else
        role.cache_bytes = reported, role.source = "reported";
    return role;
}

int last_level(const Topology& topo) {
    for (int level = 4; level >= 1; --level)
        if (const Cache* c = topo.find_cache(level); c && c->size_bytes) return level;
    return 0;
}

}  // namespace

std::vector<DefaultSize> default_points(const Topology& topo, int threads, const MeasuredCaches& measured) {
    const auto t = static_cast<std::uint64_t>(threads);
    // Half a cache per thread, in whole cache lines.
    const SizeRole l1 = cache_role(topo, 1, measured.l1, 32ULL << 10);
    const SizeRole l2 = cache_role(topo, 2, measured.l2, 1ULL << 20);
    std::vector<DefaultSize> out{{t * (l1.cache_bytes / 2 / 64 * 64), l1}, {t * (l2.cache_bytes / 2 / 64 * 64), l2}};
    const std::uint64_t llc = effective_llc_bytes(topo, measured.llc_total);
    const int llc_level = last_level(topo);
    const std::string llc_name = llc_level ? "L" + std::to_string(llc_level) : "LLC";
    const char* llc_source = measured.llc_total && llc == measured.llc_total ? "measured" : "reported";
    // The shared last level, only where the probe found it: a VM may report one it does not give.
    if (measured.llc_total && llc_level >= 3) {
        const std::uint64_t half = llc / 2 / 64 * 64;
        if (half > out.back().bytes) out.push_back({half, {llc_name + "/2", llc_name, llc, llc_source}});
    }
    // Capped at 1 GiB so the default sweep stays short where a VM reports a huge LLC that it
    // does not really give; each result records how its arrays compare with the LLC.
    // Whole MiB, so that a measured last level does not give an odd-looking size.
    const std::uint64_t mib = 1ULL << 20;
    const std::uint64_t sixteen_llc = (16 * llc + mib - 1) / mib * mib;
    const std::uint64_t dram = std::clamp<std::uint64_t>(sixteen_llc, 64 * mib, 1ULL << 30);
    out.push_back({dram, {"DRAM", llc ? llc_name : "", llc, llc ? llc_source : "assumed"}});
    return out;
}

std::vector<std::uint64_t> default_sizes(const Topology& topo, int threads, const MeasuredCaches& measured) {
    std::vector<std::uint64_t> out;
    for (const auto& d : default_points(topo, threads, measured)) out.push_back(d.bytes);
    return out;
}

}  // namespace suite
