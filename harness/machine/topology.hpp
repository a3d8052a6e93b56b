#pragma once
// The machine as hwloc sees it: packages, NUMA nodes, cores, PUs, caches and node distances,
// copied into plain structs so that nothing outside topology.cpp touches hwloc. Tests load
// other machines through hwloc's own HWLOC_SYNTHETIC / HWLOC_XMLFILE / HWLOC_FSROOT variables.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

namespace suite {

struct Pu {
    int os_index = -1;   // the number the OS (and --pin lists) use
    int core = -1;       // logical index of its core
    int smt_rank = 0;    // 0 for the first PU of a core, 1 for its hyperthread sibling, ...
    int package = -1;    // logical index of its package (socket)
    int numa_node = -1;  // OS index of its NUMA node
};

struct NumaNode {
    int os_index = -1;
    std::uint64_t memory_bytes = 0;
    std::vector<int> cpus;  // OS indexes of its PUs
};

struct Cache {
    int level = 0;
    std::string type;  // "data", "unified", "instruction"
    std::uint64_t size_bytes = 0;
    int line_bytes = 0;
    int instances = 0;         // how many such caches the machine has
    int pus_per_instance = 0;  // how many PUs share one
};

struct Topology {
    bool this_system = true;  // false when loaded from a synthetic or XML description
    int packages = 0;
    int cores = 0;
    std::vector<Pu> pus;
    std::vector<NumaNode> nodes;
    std::vector<Cache> caches;                // one entry per distinct (level, type)
    std::vector<std::vector<int>> distances;  // node x node, relative latency; empty if unknown
    std::uint64_t memory_bytes = 0;
    std::string cpu_model;  // the CPUID brand string on x86, the MIDR-named core on aarch64 (else hwloc's CPUModel of
                            // the first package), "" if unknown
    // The CPU mask the process was started with (taskset, a cgroup cpuset, a batch scheduler):
    // on this system the topology above is restricted to it, so `all`, `compact`, `scatter`
    // and the default sweep use the allowed PUs only. machine_cpus lists every PU of the
    // machine, mask_cpus the allowed ones; both empty for a synthetic or XML topology.
    std::vector<int> machine_cpus;
    std::vector<int> mask_cpus;
    bool mask_restricted() const { return mask_cpus.size() < machine_cpus.size(); }

    // hwloc's view of the machine this process runs on (honouring hwloc's environment variables).
    // whole_machine: not restricted to the process's CPU mask (what suite-mpi records of a host
    // whose ranks were each given a part of it).
    static Topology load(bool whole_machine = false);
    // From now on, load() restricts to `cpus` instead of the mask the process started with:
    // suite-mpi calls it once it has bound the process to its rank's share of the host.
    static void adopt_mask(const std::vector<int>& cpus);

    int pu_count() const { return static_cast<int>(pus.size()); }
    const Pu* find_pu(int os_index) const;
    const NumaNode* find_node(int os_index) const;
    // The data or unified cache of `level`, nullptr if hwloc reports none.
    const Cache* find_cache(int level) const;
    // All instances of the last level (data or unified) together, 0 if hwloc reports none: a
    // DRAM-sized array must be larger than the total, not than one slice.
    std::uint64_t last_level_cache_total_bytes() const;
};

nlohmann::json to_json(const Topology& topo);
// CPU numbers as taskset and --pin write them: {0,1,2,3,8} -> "0-3,8".
std::string format_cpu_list(const std::vector<int>& cpus);
std::string format_table(const Topology& topo);

}  // namespace suite
