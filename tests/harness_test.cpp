// In-process tests of the harness pieces that do not need the binary: statistics, pinning
// order on synthetic multi-socket machines, remote-node choice, page histograms, the runner.
#include <gtest/gtest.h>

#include <cstdlib>

#include <omp.h>

#include "harness/placement.hpp"
#include "harness/plan.hpp"
#include "harness/runner.hpp"
#include "harness/stats.hpp"
#include "harness/team.hpp"
#include "harness/topology.hpp"
#include "harness/units.hpp"

using namespace suite;

namespace {

// 2 packages x 1 NUMA node x 2 cores x 2 hyperthreads; OS numbering like Linux on Intel:
// first hyperthreads 0-3, siblings 4-7.
Topology two_socket() {
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

}  // namespace

TEST(Stats, SummaryOfKnownSample) {
    TimeStats s = summarise({4.0, 1.0, 3.0, 2.0});
    EXPECT_DOUBLE_EQ(s.min, 1.0);
    EXPECT_DOUBLE_EQ(s.max, 4.0);
    EXPECT_DOUBLE_EQ(s.median, 2.5);
    EXPECT_DOUBLE_EQ(s.mean, 2.5);
    EXPECT_NEAR(s.cv, 1.2909944487358056 / 2.5, 1e-12);  // sample standard deviation / mean
    EXPECT_DOUBLE_EQ(summarise({7.0}).cv, 0.0);
    EXPECT_THROW(summarise({}), std::invalid_argument);
}

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

TEST(Plan, RemoteIsResolvedForEveryTeamBeforeAnythingRuns) {
    Topology t = two_socket();
    RunOptions o;
    o.kernels = "triad";
    o.size = "1MiB";
    o.placement = "remote";
    o.threads = "1-2";  // compact: CPUs 0 and 1, both on node 0, so node 1 is remote
    EXPECT_EQ(make_plan(o, t).points.size(), 2u);
    o.pin = "scatter";  // CPUs 0 and 2: the two threads cover both nodes
    try {
        make_plan(o, t);
        FAIL() << "remote with threads on every node was accepted";
    } catch (const UsageError& e) {
        EXPECT_NE(std::string(e.what()).find("no node is remote"), std::string::npos) << e.what();
    }
}

TEST(Plan, KernelsValidateTheirConfigurationUpFront) {
    Topology t = two_socket();
    RunOptions o;
    o.kernels = "latency";
    o.size = "1KiB";
    o.threads = "8";  // 16 lines for 8 threads is enough ...
    EXPECT_EQ(make_plan(o, t).points.size(), 1u);
    o.size = "512B";  // ... 8 lines are not
    EXPECT_THROW(make_plan(o, t), UsageError);
    o.kernels = "add";
    o.size = "200TiB";  // random indices are 32-bit
    o.patterns = "random";
    EXPECT_THROW(make_plan(o, t), UsageError);
    o.size = "1MiB";
    o.stores = "nt";  // non-temporal stores are for the sequential pattern
    EXPECT_THROW(make_plan(o, t), UsageError);
}

TEST(Plan, DefaultSizesFollowTheCaches) {
    Topology t = two_socket();
    t.caches = {{1, "data", 48 << 10, 64, 4, 1}, {2, "unified", 2 << 20, 64, 4, 1}, {3, "unified", 32 << 20, 64, 2, 4}};
    // Half an L1d and half an L2 per thread, and 16x the two L3 instances together (1 GiB).
    EXPECT_EQ(default_sizes(t, 1), (std::vector<std::uint64_t>{24 << 10, 1 << 20, 1ull << 30}));
    EXPECT_EQ(default_sizes(t, 4), (std::vector<std::uint64_t>{96 << 10, 4 << 20, 1ull << 30}));
    EXPECT_EQ(t.last_level_cache_total_bytes(), 64ull << 20);
}

TEST(Plan, DefaultSweepFitsAManyThreadMachine) {
    // 256 PUs, 32 KiB L1d: half an L1 for the whole team would leave each thread 64 bytes.
    Topology t;
    t.packages = 2;
    t.cores = 128;
    for (int cpu = 0; cpu < 256; ++cpu) t.pus.push_back({cpu, cpu % 128, cpu / 128, (cpu % 128) / 64, (cpu % 128) / 64});
    t.nodes = {{0, 1ull << 40, {}}, {1, 1ull << 40, {}}};
    t.caches = {{1, "data", 32 << 10, 64, 128, 2}, {2, "unified", 1 << 20, 64, 128, 2}, {3, "unified", 32 << 20, 64, 16, 16}};
    if (omp_get_thread_limit() < 256) GTEST_SKIP() << "OMP_THREAD_LIMIT is below 256";
    Plan plan = make_plan(RunOptions{}, t);
    EXPECT_FALSE(plan.points.empty());
    for (const auto& p : plan.points)
        if (p.threads == 256 && p.size < (1u << 20)) ADD_FAILURE() << "an L1 point of " << p.size << " B for 256 threads";
}
