#include "harness/machine/topology.hpp"

#include <hwloc.h>
#include <sched.h>

#if defined(__x86_64__) || defined(__i386__)
#include <cpuid.h>
#endif

#include <algorithm>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "harness/common/units.hpp"
#include "harness/machine/cpu_model.hpp"

namespace suite {

namespace {

struct HwlocTopology {
    hwloc_topology_t t = nullptr;
    HwlocTopology() {
        if (hwloc_topology_init(&t) != 0 || hwloc_topology_load(t) != 0)
            throw std::runtime_error("hwloc could not load the machine topology");
    }
    ~HwlocTopology() { hwloc_topology_destroy(t); }
    HwlocTopology(const HwlocTopology&) = delete;
    HwlocTopology& operator=(const HwlocTopology&) = delete;
};

int ancestor_index(hwloc_topology_t t, hwloc_obj_t obj, hwloc_obj_type_t type) {
    hwloc_obj_t a = hwloc_get_ancestor_obj_by_type(t, type, obj);
    return a ? static_cast<int>(a->logical_index) : -1;
}

// The process's CPU mask as it was when the program started, before any thread was pinned
// (pinning the team pins the main thread too, and a later load must not mistake that for the
// mask the user gave).
// suite-mpi replaces it with the rank's share of its host (Topology::adopt_mask).
std::vector<int> startup_mask = [] {
    std::vector<int> cpus;
    cpu_set_t set;
    CPU_ZERO(&set);
    if (sched_getaffinity(0, sizeof set, &set) == 0)
        for (int c = 0; c < CPU_SETSIZE; ++c)
            if (CPU_ISSET(c, &set)) cpus.push_back(c);
    return cpus;
}();

// Restricts the topology to the startup mask; fills machine_cpus and mask_cpus.
void restrict_to_mask(hwloc_topology_t t, Topology& topo) {
    hwloc_const_cpuset_t all = hwloc_topology_get_topology_cpuset(t);
    for (int c = hwloc_bitmap_first(all); c >= 0; c = hwloc_bitmap_next(all, c)) topo.machine_cpus.push_back(c);
    hwloc_bitmap_t mask = hwloc_bitmap_alloc();
    for (int c : startup_mask) hwloc_bitmap_set(mask, static_cast<unsigned>(c));
    hwloc_bitmap_and(mask, mask, all);
    if (!hwloc_bitmap_iszero(mask) && !hwloc_bitmap_isequal(mask, all) && hwloc_topology_restrict(t, mask, 0) != 0) {
        hwloc_bitmap_free(mask);
        throw std::runtime_error("hwloc could not restrict the topology to this process's CPU mask");
    }
    if (hwloc_bitmap_iszero(mask)) hwloc_bitmap_copy(mask, all);  // a mask hwloc does not know: nothing to restrict
    for (int c = hwloc_bitmap_first(mask); c >= 0; c = hwloc_bitmap_next(mask, c)) topo.mask_cpus.push_back(c);
    hwloc_bitmap_free(mask);
}

// The processor's brand string (CPUID 0x80000002..4), as hwloc's x86 backend reads it; "" where
// there is none. hwloc's CPUModel comes from that backend or, where the backend does not run, from
// /proc/cpuinfo, and the two differ on a VM ("Oxide Virtual Turin-like Processor" against "AMD
// EPYC"): one unchanged machine was seen under both, 1 run in 12, which split its history in two
// machines. Read here, it is the same every time.
std::string cpuid_brand() {
#if defined(__x86_64__) || defined(__i386__)
    if (__get_cpuid_max(0x80000000, nullptr) < 0x80000004) return "";
    char brand[49] = {};
    for (unsigned i = 0; i < 3; ++i) {
        unsigned regs[4] = {};
        __get_cpuid(0x80000002 + i, &regs[0], &regs[1], &regs[2], &regs[3]);
        std::memcpy(brand + 16 * i, regs, 16);
    }
    return brand;
#else
    return "";
#endif
}

const char* cache_type_name(hwloc_obj_cache_type_t t) {
    switch (t) {
        case HWLOC_OBJ_CACHE_DATA:
            return "data";
        case HWLOC_OBJ_CACHE_INSTRUCTION:
            return "instruction";
        default:
            return "unified";
    }
}

}  // namespace

void Topology::adopt_mask(const std::vector<int>& cpus) { startup_mask = cpus; }

Topology Topology::load(bool whole_machine) {
    HwlocTopology h;
    hwloc_topology_t t = h.t;
    Topology topo;
    topo.this_system = hwloc_topology_is_thissystem(t) != 0;
    if (topo.this_system && !whole_machine) restrict_to_mask(t, topo);
    topo.packages = std::max(1, hwloc_get_nbobjs_by_type(t, HWLOC_OBJ_PACKAGE));
    topo.cores = hwloc_get_nbobjs_by_type(t, HWLOC_OBJ_CORE);
    if (hwloc_obj_t pkg = hwloc_get_obj_by_type(t, HWLOC_OBJ_PACKAGE, 0))
        if (const char* model = hwloc_obj_get_info_by_name(pkg, "CPUModel")) topo.cpu_model = model;
    // This machine's own processor: its brand string, whichever hwloc backend ran (a topology
    // read from a file keeps the file's model).
    if (topo.this_system)
        if (std::string brand = cpuid_brand(); !brand.empty()) topo.cpu_model = brand;
#if defined(__aarch64__)
    // An Arm CPU has no brand string: its MIDR fields, named where the table knows the core.
    if (topo.this_system) {
        std::ifstream in("/proc/cpuinfo");
        std::stringstream text;
        text << in.rdbuf();
        if (std::string midr = arm_cpu_model(text.str()); !midr.empty()) topo.cpu_model = midr;
    }
#endif

    int nnodes = hwloc_get_nbobjs_by_type(t, HWLOC_OBJ_NUMANODE);
    for (int i = 0; i < nnodes; ++i) {
        hwloc_obj_t n = hwloc_get_obj_by_type(t, HWLOC_OBJ_NUMANODE, i);
        NumaNode node;
        node.os_index = static_cast<int>(n->os_index);
        node.memory_bytes = n->attr ? n->attr->numanode.local_memory : 0;
        topo.memory_bytes += node.memory_bytes;
        topo.nodes.push_back(node);
    }

    int npus = hwloc_get_nbobjs_by_type(t, HWLOC_OBJ_PU);
    for (int i = 0; i < npus; ++i) {
        hwloc_obj_t p = hwloc_get_obj_by_type(t, HWLOC_OBJ_PU, i);
        Pu pu;
        pu.os_index = static_cast<int>(p->os_index);
        pu.package = std::max(0, ancestor_index(t, p, HWLOC_OBJ_PACKAGE));
        hwloc_obj_t core = hwloc_get_ancestor_obj_by_type(t, HWLOC_OBJ_CORE, p);
        pu.core = core ? static_cast<int>(core->logical_index) : i;
        if (core) {
            for (unsigned k = 0; k < core->arity; ++k)
                if (core->children[k] == p) pu.smt_rank = static_cast<int>(k);
        }
        // The NUMA node whose cpuset holds this PU.
        for (int k = 0; k < nnodes; ++k) {
            hwloc_obj_t n = hwloc_get_obj_by_type(t, HWLOC_OBJ_NUMANODE, k);
            if (hwloc_bitmap_isset(n->cpuset, p->os_index)) {
                pu.numa_node = static_cast<int>(n->os_index);
                topo.nodes[k].cpus.push_back(pu.os_index);
                break;
            }
        }
        topo.pus.push_back(pu);
    }
    if (topo.cores == 0) topo.cores = npus;

    std::map<std::pair<int, std::string>, Cache> caches;
    for (hwloc_obj_type_t type :
         {HWLOC_OBJ_L1CACHE, HWLOC_OBJ_L2CACHE, HWLOC_OBJ_L3CACHE, HWLOC_OBJ_L4CACHE, HWLOC_OBJ_L5CACHE}) {
        int n = hwloc_get_nbobjs_by_type(t, type);
        for (int i = 0; i < n; ++i) {
            hwloc_obj_t c = hwloc_get_obj_by_type(t, type, i);
            Cache cache;
            cache.level = static_cast<int>(c->attr->cache.depth);
            cache.type = cache_type_name(c->attr->cache.type);
            cache.size_bytes = c->attr->cache.size;
            cache.line_bytes = static_cast<int>(c->attr->cache.linesize);
            cache.pus_per_instance = hwloc_bitmap_weight(c->cpuset);
            auto [it, fresh] = caches.emplace(std::make_pair(cache.level, cache.type), cache);
            it->second.instances += 1;
        }
    }
    for (auto& [key, cache] : caches) topo.caches.push_back(cache);

    hwloc_distances_s* dist = nullptr;
    unsigned nr = 1;
    if (hwloc_distances_get_by_type(t, HWLOC_OBJ_NUMANODE, &nr, &dist, HWLOC_DISTANCES_KIND_MEANS_LATENCY, 0) == 0 &&
        nr >= 1 && dist) {
        std::map<int, unsigned> pos;  // os index -> row
        for (unsigned i = 0; i < dist->nbobjs; ++i) pos[static_cast<int>(dist->objs[i]->os_index)] = i;
        // Only a matrix that covers every node is used; a partial one would misplace rows.
        bool complete = true;
        for (const auto& n : topo.nodes) complete = complete && pos.count(n.os_index) == 1;
        if (complete) {
            topo.distances.assign(topo.nodes.size(), std::vector<int>(topo.nodes.size(), 0));
            for (std::size_t a = 0; a < topo.nodes.size(); ++a)
                for (std::size_t b = 0; b < topo.nodes.size(); ++b)
                    topo.distances[a][b] = static_cast<int>(
                        dist->values[pos.at(topo.nodes[a].os_index) * dist->nbobjs + pos.at(topo.nodes[b].os_index)]);
        }
        hwloc_distances_release(t, dist);
    }
    return topo;
}

const Pu* Topology::find_pu(int os_index) const {
    for (const auto& p : pus)
        if (p.os_index == os_index) return &p;
    return nullptr;
}

const NumaNode* Topology::find_node(int os_index) const {
    for (const auto& n : nodes)
        if (n.os_index == os_index) return &n;
    return nullptr;
}

const Cache* Topology::find_cache(int level) const {
    for (const auto& c : caches)
        if (c.level == level && c.type != "instruction") return &c;
    return nullptr;
}

namespace {
const Cache* last_level(const std::vector<Cache>& caches) {
    const Cache* last = nullptr;
    for (const auto& c : caches)
        if (c.type != "instruction" && (!last || c.level > last->level)) last = &c;
    return last;
}
}  // namespace

std::uint64_t Topology::last_level_cache_total_bytes() const {
    const Cache* c = last_level(caches);
    return c ? c->size_bytes * static_cast<std::uint64_t>(c->instances) : 0;
}

std::string format_cpu_list(const std::vector<int>& cpus) {
    std::vector<int> v = cpus;
    std::sort(v.begin(), v.end());
    std::string out;
    for (std::size_t i = 0; i < v.size();) {
        std::size_t j = i;
        while (j + 1 < v.size() && v[j + 1] == v[j] + 1) ++j;
        out += (out.empty() ? "" : ",") + std::to_string(v[i]) + (j > i ? "-" + std::to_string(v[j]) : "");
        i = j + 1;
    }
    return out;
}

nlohmann::json to_json(const Topology& topo) {
    nlohmann::json j;
    j["cpu_model"] = topo.cpu_model;
    j["packages"] = topo.packages;
    j["cores"] = topo.cores;
    j["pus"] = topo.pu_count();
    j["memory_bytes"] = topo.memory_bytes;
    j["numa_nodes"] = nlohmann::json::array();
    for (const auto& n : topo.nodes)
        j["numa_nodes"].push_back({{"os_index", n.os_index}, {"memory_bytes", n.memory_bytes}, {"cpus", n.cpus}});
    j["caches"] = nlohmann::json::array();
    for (const auto& c : topo.caches)
        j["caches"].push_back({{"level", c.level},
                               {"type", c.type},
                               {"size_bytes", c.size_bytes},
                               {"line_bytes", c.line_bytes},
                               {"instances", c.instances},
                               {"pus_per_instance", c.pus_per_instance}});
    j["numa_distances"] = topo.distances;
    j["pu_map"] = nlohmann::json::array();
    for (const auto& p : topo.pus)
        j["pu_map"].push_back(
            {{"os_index", p.os_index},
             {"core", p.core},
             {"smt_rank", p.smt_rank},
             {"package", p.package},
             {"numa_node", p.numa_node >= 0 ? nlohmann::json(p.numa_node) : nlohmann::json(nullptr)}});
    j["this_system"] = topo.this_system;
    if (topo.this_system)
        j["cpu_mask"] = {{"cpus", format_cpu_list(topo.mask_cpus)},
                         {"machine_pus", topo.machine_cpus.size()},
                         {"restricted", topo.mask_restricted()}};
    return j;
}

std::string format_table(const Topology& topo) {
    std::ostringstream o;
    if (!topo.cpu_model.empty()) o << "CPU: " << topo.cpu_model << "\n";
    o << "Machine: " << topo.packages << " package(s), " << topo.nodes.size() << " NUMA node(s), " << topo.cores
      << " core(s), " << topo.pu_count() << " PU(s), " << format_bytes(topo.memory_bytes) << " memory (hwloc)\n";
    if (!topo.this_system) o << "  (a synthetic or XML topology, not this machine's)\n";
    if (topo.mask_restricted())
        o << "  CPU mask: " << format_cpu_list(topo.mask_cpus) << ", " << topo.mask_cpus.size() << " of the machine's "
          << topo.machine_cpus.size()
          << " PUs (taskset, a cgroup or the batch scheduler); everything below is what this process may use\n";
    o << "\nNUMA nodes\n  node  memory      cpus\n";
    for (const auto& n : topo.nodes) {
        std::ostringstream cpus;
        for (std::size_t i = 0; i < n.cpus.size(); ++i) cpus << (i ? "," : "") << n.cpus[i];
        char line[160];
        std::snprintf(line, sizeof line, "  %-5d %-11s %s\n", n.os_index, format_bytes(n.memory_bytes).c_str(),
                      cpus.str().c_str());
        o << line;
    }
    if (!topo.distances.empty()) {
        o << "\nNUMA distances\n      ";
        for (const auto& n : topo.nodes) o << "node" << n.os_index << " ";
        o << "\n";
        for (std::size_t a = 0; a < topo.nodes.size(); ++a) {
            o << "  node" << topo.nodes[a].os_index;
            for (int d : topo.distances[a]) {
                char c[16];
                std::snprintf(c, sizeof c, " %5d", d);
                o << c;
            }
            o << "\n";
        }
    }
    o << "\nCaches (as reported by hwloc)\n  level  type         size      line  instances  PUs each\n";
    for (const auto& c : topo.caches) {
        char line[160];
        std::snprintf(line, sizeof line, "  L%-5d %-12s %-9s %-5d %-10d %d\n", c.level, c.type.c_str(),
                      format_bytes(c.size_bytes).c_str(), c.line_bytes, c.instances, c.pus_per_instance);
        o << line;
    }
    o << "\nPUs\n  cpu  core  smt  package  node\n";
    for (const auto& p : topo.pus) {
        char line[96];
        std::snprintf(line, sizeof line, "  %-4d %-5d %-4d %-8d %d\n", p.os_index, p.core, p.smt_rank, p.package,
                      p.numa_node);
        o << line;
    }
    return o.str();
}

}  // namespace suite
