#pragma once
// Where an array's pages should live. A PlacementSpec is what the user asked for; resolve_policy()
// turns it, given the CPUs the team may run on, into the one policy an Arena
// (harness/kernel/arena.hpp) applies to every array it hands out, and which records afterwards
// where the pages really went.
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "harness/common/choice_table.hpp"
#include "harness/kernel/arena.hpp"
#include "harness/machine/topology.hpp"

namespace suite {

struct PlacementSpec {
    PlacementKind kind = PlacementKind::local;
    int node = -1;     // for PlacementKind::node
    std::string text;  // as given
};

struct PlacementBehaviour {
    PlacementKind kind = PlacementKind::local;
    bool takes_node = false;  // named "NAME:N", N a NUMA node's number
};

// --placement's kinds (local, node:N, remote, interleave), one table: parse_placement, its
// messages and --help read it.
const ChoiceTable<PlacementBehaviour>& placement_kinds();

// The name of `k` in placement_kinds(): what a plan's placement text is for a kind it sets itself.
const std::string& placement_name(PlacementKind k);

// The forms a user writes, "NAME:N" for a kind that takes a node: "local, node:N, remote, interleave".
std::string placement_forms();
// The forms of the kinds other than `k`, the last two joined by "or": "local, node:N or interleave".
std::string placement_forms_other_than(PlacementKind k);

// A kind of placement_kinds(), node:N with a node number. Throws UsageError for a node that does
// not exist and for a kind that needs 2 NUMA nodes (remote) on a machine with one.
PlacementSpec parse_placement(std::string_view text, const Topology& topo);

// The node that remote places arrays on: one that none of `thread_nodes` is, the nearest of
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
