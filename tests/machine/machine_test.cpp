// In-process tests of the machine layer: pinning order on synthetic multi-socket machines,
// remote-node choice, the topology hwloc reads, page histograms.
#include <gtest/gtest.h>

#include <cstdlib>
#include <cstring>
#include <string>
#if defined(__x86_64__)
#include <cpuid.h>
#endif

#include <omp.h>

#include "harness/common/units.hpp"
#include "harness/kernel/arena.hpp"
#include "harness/machine/placement.hpp"
#include "harness/machine/team.hpp"
#include "harness/machine/topology.hpp"
#include "tests/synthetic_topology.hpp"

using namespace suite;
using suite::testing::two_socket;

TEST(Pinning, CompactFillsCoresOfTheFirstSocketFirstThenHyperthreads) {
    Topology t = two_socket();
    EXPECT_EQ(pin_order(t, parse_pin("compact", t)), (std::vector<int>{0, 1, 2, 3, 4, 5, 6, 7}));
}

TEST(Pinning, ScatterAlternatesNodes) {
    Topology t = two_socket();
    EXPECT_EQ(pin_order(t, parse_pin("scatter", t)), (std::vector<int>{0, 2, 1, 3, 4, 6, 5, 7}));
}

TEST(Pinning, ListIsTakenAsGivenAndValidated) {
    Topology t = two_socket();
    EXPECT_EQ(pin_order(t, parse_pin("6,0-1", t)), (std::vector<int>{6, 0, 1}));
    EXPECT_TRUE(pin_order(t, parse_pin("none", t)).empty());
    EXPECT_THROW(parse_pin("8", t), UsageError);
    EXPECT_THROW(parse_pin("1,1", t), UsageError);
    EXPECT_THROW(parse_pin("compcat", t), UsageError);
}

TEST(Placement, RemoteIsTheNearestNodeTheThreadsDoNotUse) {
    Topology t = two_socket();
    EXPECT_EQ(choose_remote_node(t, {0}), 1);
    EXPECT_EQ(choose_remote_node(t, {1}), 0);
    EXPECT_EQ(choose_remote_node(t, {0, 1}), -1);
    // Four nodes in a ring: from node 0, node 1 (one hop) is chosen over node 2 (two hops).
    Topology ring = t;
    ring.nodes = {{0, 0, {}}, {1, 0, {}}, {2, 0, {}}, {3, 0, {}}};
    ring.distances = {{10, 16, 22, 16}, {16, 10, 16, 22}, {22, 16, 10, 16}, {16, 22, 16, 10}};
    EXPECT_EQ(choose_remote_node(ring, {0}), 1);
    EXPECT_EQ(choose_remote_node(ring, {0, 1}), 2);  // 2 and 3 tie at 38: the lower index wins
    EXPECT_EQ(choose_remote_node(ring, {0, 1, 2}), 3);
}

TEST(Placement, ParseRejectsMissingNodesAndRemoteOnOneNode) {
    Topology t = two_socket();
    EXPECT_EQ(parse_placement("node:1", t).node, 1);
    EXPECT_EQ(parse_placement("remote", t).kind, PlacementKind::remote);
    EXPECT_THROW(parse_placement("node:2", t), UsageError);
    EXPECT_THROW(parse_placement("node:x", t), UsageError);
    Topology one = t;
    one.nodes.resize(1);
    EXPECT_THROW(parse_placement("remote", one), UsageError);
}

TEST(Topology, SyntheticTwoPackageMachineThroughHwloc) {
    // hwloc builds this machine from its own description, as it would from a captured one.
    setenv("HWLOC_SYNTHETIC", "pack:2 numa:1 l3:1 core:4 pu:2", 1);
    Topology t = Topology::load();
    unsetenv("HWLOC_SYNTHETIC");
    EXPECT_FALSE(t.this_system);
    EXPECT_EQ(t.packages, 2);
    EXPECT_EQ(t.nodes.size(), 2u);
    EXPECT_EQ(t.cores, 8);
    EXPECT_EQ(t.pu_count(), 16);
    EXPECT_EQ(t.nodes[1].cpus.size(), 8u);
    // scatter puts thread 0 and thread 1 on different packages
    auto order = pin_order(t, parse_pin("scatter", t));
    ASSERT_GE(order.size(), 2u);
    EXPECT_NE(t.find_pu(order[0])->package, t.find_pu(order[1])->package);
    auto compact = pin_order(t, parse_pin("compact", t));
    EXPECT_EQ(t.find_pu(compact[0])->package, t.find_pu(compact[3])->package);
    EXPECT_NE(t.find_pu(compact[0])->core, t.find_pu(compact[1])->core);  // one PU per core first
}

TEST(Topology, ThisMachineIsConsistent) {
    Topology t = Topology::load();
    EXPECT_TRUE(t.this_system);
    ASSERT_GE(t.pu_count(), 1);
    ASSERT_GE(t.nodes.size(), 1u);
    std::size_t cpus_in_nodes = 0;
    for (const auto& n : t.nodes) cpus_in_nodes += n.cpus.size();
    EXPECT_EQ(cpus_in_nodes, t.pus.size());
}

// The model is part of the machine's fingerprint in the history: it must not depend on which of
// hwloc's backends answered (this VM was seen as "AMD EPYC", /proc/cpuinfo's, in 1 run of 12,
// and the x86 backend's brand string otherwise). On x86 it is the CPUID brand string, every time.
TEST(Topology, TheCpuModelIsTheSameEveryTime) {
    const std::string first = Topology::load().cpu_model;
    EXPECT_FALSE(first.empty());
    for (int i = 0; i < 20; ++i) ASSERT_EQ(Topology::load().cpu_model, first) << "load " << i;
#if defined(__x86_64__)
    unsigned regs[12] = {};
    for (unsigned i = 0; i < 3; ++i)
        __get_cpuid(0x80000002 + i, &regs[4 * i], &regs[4 * i + 1], &regs[4 * i + 2], &regs[4 * i + 3]);
    char brand[49] = {};
    std::memcpy(brand, regs, 48);
    EXPECT_EQ(first, std::string(brand));
#endif
}

TEST(Placement, HistogramFindsEveryTouchedPageOnItsNode) {
    Topology topo = Topology::load();
    for (const char* where : {"local", "node:0", "interleave"}) {
        PlacementSpec spec = parse_placement(where, topo);
        Arena arena(resolve_policy(spec, topo, {0}));
        const std::size_t n = 1 << 20;  // 8 MiB
        double* a = arena.allocate<double>("a", n);
        double* untouched = arena.allocate<double>("untouched", n);
        (void)untouched;
        for (std::size_t i = 0; i < n; ++i) a[i] = 1.0;
        auto pages = arena.observe();
        ASSERT_EQ(pages.size(), 2u);
        EXPECT_EQ(pages[0].name, "a");
        EXPECT_EQ(pages[0].pages, n * sizeof(double) / 4096);
        EXPECT_EQ(pages[0].pages_not_present, 0u) << where << ": " << pages[0].error;
        std::uint64_t counted = 0;
        for (auto [node, count] : pages[0].pages_per_node) {
            EXPECT_NE(topo.find_node(node), nullptr) << "page on unknown node " << node;
            counted += count;
        }
        EXPECT_EQ(counted, pages[0].pages);
        if (topo.nodes.size() == 1) {
            EXPECT_EQ(pages[0].pages_per_node[topo.nodes[0].os_index], pages[0].pages) << where;
        }
        // Never-touched pages are not present: the histogram reports what happened, not what was asked.
        EXPECT_EQ(pages[1].pages_not_present, pages[1].pages) << where;
    }
}
