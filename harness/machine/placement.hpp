#pragma once
// Where an array's pages should live. A PlacementSpec is what the user asked for; resolve_policy()
// turns it, given the CPUs the team may run on, into the one policy an Arena
// (harness/kernel/arena.hpp) applies to every array it hands out, and which records afterwards
// where the pages really went.
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "harness/kernel/arena.hpp"
#include "harness/machine/topology.hpp"

namespace suite {

struct PlacementSpec {
    PlacementKind kind = PlacementKind::local;
    int node = -1;     // for PlacementKind::node
    std::string text;  // as given
};

// "local" | "node:N" | "remote" | "interleave". Throws UsageError for a node that does not
// exist and for "remote" on a machine with one NUMA node.
PlacementSpec parse_placement(std::string_view text, const Topology& topo);

// The node that "remote" places arrays on: one that none of `thread_nodes` is, the nearest of
// those by NUMA distance to the threads (the usual one-hop "scenario A"), lowest index on ties.
// -1 when the threads cover every node.
int choose_remote_node(const Topology& topo, const std::vector<int>& thread_nodes);

// "thp" | "none" | "system". Throws UsageError for anything else, and for "thp" where the
// kernel has no transparent huge pages (no `thp_enabled` file, the kernel's unless a test names
// another: madvise would fail); where they are switched off ("never") it sets `note`.
HugePages parse_hugepages(std::string_view text,
                          const std::string& thp_enabled = "/sys/kernel/mm/transparent_hugepage/enabled",
                          std::string* note = nullptr);

// The policy of `spec` for threads that may run on `thread_cpus` (OS CPU numbers). Throws
// UsageError when "remote" has no node left that the threads do not use.
MemoryPolicy resolve_policy(const PlacementSpec& spec, const Topology& topo, const std::vector<int>& thread_cpus);

}  // namespace suite
