#pragma once
// A synthetic machine for in-process tests of pinning, placement and planning.
#include "harness/machine/topology.hpp"

namespace suite::testing {

// 2 packages x 1 NUMA node x 2 cores x 2 hyperthreads; OS numbering like Linux on Intel:
// first hyperthreads 0-3, siblings 4-7.
inline Topology two_socket() {
    Topology t;
    t.packages = 2;
    t.cores = 4;
    for (int cpu = 0; cpu < 8; ++cpu) {
        Pu p;
        p.os_index = cpu;
        p.core = cpu % 4;
        p.smt_rank = cpu / 4;
        p.package = (cpu % 4) / 2;
        p.numa_node = p.package;
        t.pus.push_back(p);
    }
    t.nodes = {{0, 1ull << 30, {0, 1, 4, 5}}, {1, 1ull << 30, {2, 3, 6, 7}}};
    t.distances = {{10, 21}, {21, 10}};
    return t;
}

}  // namespace suite::testing
