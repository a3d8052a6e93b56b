// In-process tests of planning: every point validated before anything runs, the default sizes.
#include <gtest/gtest.h>

#include <cstdlib>

#include <omp.h>

#include "app/suite/defaults.hpp"
#include "harness/common/units.hpp"
#include "harness/machine/topology.hpp"
#include "harness/measure/plan.hpp"
#include "harness/measure/runner.hpp"
#include "tests/synthetic_topology.hpp"

using namespace suite;
using suite::testing::two_socket;

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

TEST(Plan, DefaultPointsCarryTheCacheTheyCameFrom) {
    Topology t = two_socket();
    t.caches = {{1, "data", 48 << 10, 64, 4, 1}, {2, "unified", 2 << 20, 64, 4, 1}, {3, "unified", 32 << 20, 64, 2, 4}};
    // Reported caches only: no L3/2 (a VM may report a last level it does not give).
    auto reported = default_points(t, 2);
    ASSERT_EQ(reported.size(), 3u);
    EXPECT_EQ(reported[0].role.name, "L1/2");
    EXPECT_EQ(reported[0].role.cache_bytes, 48u << 10);
    EXPECT_EQ(reported[0].role.source, "reported");
    EXPECT_EQ(reported[1].role.name, "L2/2");
    EXPECT_EQ(reported[1].bytes, 2u << 20);
    EXPECT_EQ(reported[2].role.name, "DRAM");
    EXPECT_EQ(reported[2].role.cache, "L3");
    EXPECT_EQ(reported[2].role.cache_bytes, 64ull << 20);
    // The probe measured a smaller L2 and the last level: L3/2 joins, each source said.
    const MeasuredCaches measured{0, 1 << 20, 40ull << 20};
    auto probed = default_points(t, 1, measured);
    ASSERT_EQ(probed.size(), 4u);
    EXPECT_EQ(probed[0].role.source, "reported");
    EXPECT_EQ(probed[1].role.source, "measured");
    EXPECT_EQ(probed[1].bytes, 512u << 10);
    EXPECT_EQ(probed[2].role.name, "L3/2");
    EXPECT_EQ(probed[2].bytes, 20ull << 20);
    EXPECT_EQ(probed[2].role.cache_bytes, 40ull << 20);
    EXPECT_EQ(probed[2].role.source, "measured");
    // The points of a plan carry them, per thread count.
    RunOptions o;
    o.kernels = "copy";
    o.threads = "1,2";
    o.pin = "none";
    o.measured = measured;
    const Plan plan = make_plan(o, t);
    std::vector<std::string> roles;
    for (const auto& p : plan.points) roles.push_back(p.role.name + "@" + std::to_string(p.threads));
    EXPECT_EQ(roles, (std::vector<std::string>{"L1/2@1", "L1/2@2", "L2/2@1", "L2/2@2", "L3/2@1", "L3/2@2", "DRAM@1",
                                               "DRAM@2"}));
    // Sizes given stand for themselves.
    o.sizes = "64KiB";
    for (const auto& p : make_plan(o, t).points) EXPECT_TRUE(p.role.name.empty());
}

TEST(Plan, DefaultSweepFitsAManyThreadMachine) {
    // 256 PUs, 32 KiB L1d: half an L1 for the whole team would leave each thread 64 bytes.
    Topology t;
    t.packages = 2;
    t.cores = 128;
    for (int cpu = 0; cpu < 256; ++cpu)
        t.pus.push_back({cpu, cpu % 128, cpu / 128, (cpu % 128) / 64, (cpu % 128) / 64});
    t.nodes = {{0, 1ull << 40, {}}, {1, 1ull << 40, {}}};
    t.caches = {
        {1, "data", 32 << 10, 64, 128, 2}, {2, "unified", 1 << 20, 64, 128, 2}, {3, "unified", 32 << 20, 64, 16, 16}};
    if (omp_get_thread_limit() < 256) GTEST_SKIP() << "OMP_THREAD_LIMIT is below 256";
    RunOptions o;
    o.default_sweep = default_sweep();
    Plan plan = make_plan(o, t);
    EXPECT_FALSE(plan.points.empty());
    for (const auto& p : plan.points)
        if (p.threads == 256 && p.size < (1u << 20))
            ADD_FAILURE() << "an L1 point of " << p.size << " B for 256 threads";
}
