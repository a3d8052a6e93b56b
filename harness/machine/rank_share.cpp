#include "harness/machine/rank_share.hpp"

#include <algorithm>
#include <map>
#include <set>

#include "harness/common/units.hpp"

namespace suite {

RankShare share_of(const Topology& topo, int ranks, int index) {
    if (ranks < 1 || index < 0 || index >= ranks) throw std::logic_error("share_of: rank index out of range");
    RankShare out;
    // The NUMA nodes that have CPUs under the mask, in OS order.
    std::map<int, std::vector<int>> node_cpus;
    for (const Pu& pu : topo.pus)
        if (pu.numa_node >= 0) node_cpus[pu.numa_node].push_back(pu.os_index);
    if (ranks > 1 && static_cast<int>(node_cpus.size()) == ranks) {
        auto it = node_cpus.begin();
        std::advance(it, index);
        out.cpus = it->second;
        out.layout = "numa";
    } else {
        // Whole cores in hwloc's logical order, split into `ranks` runs as equal as they can be.
        std::vector<int> cores;
        for (const Pu& pu : topo.pus)
            if (std::find(cores.begin(), cores.end(), pu.core) == cores.end()) cores.push_back(pu.core);
        std::sort(cores.begin(), cores.end());
        const int n = static_cast<int>(cores.size());
        if (ranks > n)
            throw UsageError(
                std::to_string(ranks) + " ranks were started on one host with " + std::to_string(n) +
                " core(s) (CPUs " + format_cpu_list(topo.mask_cpus.empty() ? std::vector<int>{} : topo.mask_cpus) +
                "): they would share cores; start at most one rank a core (one a NUMA node is the documented layout)");
        const int lo = index * n / ranks, hi = (index + 1) * n / ranks;
        const std::set<int> mine(cores.begin() + lo, cores.begin() + hi);
        for (const Pu& pu : topo.pus)
            if (mine.count(pu.core)) out.cpus.push_back(pu.os_index);
        out.layout = "split";
    }
    std::sort(out.cpus.begin(), out.cpus.end());
    return out;
}

bool disjoint_sets(const std::vector<std::vector<int>>& sets, const std::vector<int>& rank_of_set, std::string& clash) {
    std::map<int, std::size_t> owner;
    for (std::size_t s = 0; s < sets.size(); ++s)
        for (int cpu : sets[s]) {
            const auto [it, fresh] = owner.emplace(cpu, s);
            if (!fresh) {
                clash = "rank " + std::to_string(rank_of_set[it->second]) + " and rank " +
                        std::to_string(rank_of_set[s]) + " both have CPU " + std::to_string(cpu);
                return false;
            }
        }
    return true;
}

}  // namespace suite
