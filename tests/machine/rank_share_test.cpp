// How suite-mpi shares a host's CPUs between the ranks started on it (machine/rank_share.hpp),
// on machines hwloc builds from a description: no MPI and no such hardware needed.
#include <gtest/gtest.h>

#include <cstdlib>
#include <set>

#include "harness/common/units.hpp"
#include "harness/machine/rank_share.hpp"

using namespace suite;

namespace {

Topology synthetic(const char* description) {
    setenv("HWLOC_SYNTHETIC", description, 1);
    Topology t = Topology::load();
    unsetenv("HWLOC_SYNTHETIC");
    return t;
}

std::set<int> node_of(const Topology& t, const std::vector<int>& cpus) {
    std::set<int> nodes;
    for (int c : cpus) nodes.insert(t.find_pu(c)->numa_node);
    return nodes;
}

}  // namespace

TEST(RankShare, OneRankPerNumaNodeGetsExactlyThatNode) {
    const Topology t = synthetic("pack:2 numa:2 core:4 pu:2");  // 4 nodes of 4 cores, 2 PUs each
    ASSERT_EQ(t.nodes.size(), 4u);
    std::set<int> seen;
    for (int r = 0; r < 4; ++r) {
        const RankShare s = share_of(t, 4, r);
        EXPECT_EQ(s.layout, "numa");
        EXPECT_EQ(s.cpus.size(), 8u);
        EXPECT_EQ(node_of(t, s.cpus).size(), 1u) << "rank " << r << " spans nodes";
        EXPECT_EQ(*node_of(t, s.cpus).begin(), t.nodes[static_cast<std::size_t>(r)].os_index);
        for (int c : s.cpus) EXPECT_TRUE(seen.insert(c).second) << "CPU " << c << " given twice";
    }
    EXPECT_EQ(seen.size(), 32u);  // every CPU of the host given out
}

TEST(RankShare, OtherCountsGetEqualRunsOfWholeCores) {
    const Topology t = synthetic("pack:2 numa:1 core:4 pu:2");  // 2 nodes, 8 cores, 16 PUs
    std::set<int> seen;
    for (int r = 0; r < 4; ++r) {  // 4 ranks on 2 nodes: not one a node, so runs of 2 cores
        const RankShare s = share_of(t, 4, r);
        EXPECT_EQ(s.layout, "split");
        ASSERT_EQ(s.cpus.size(), 4u);  // 2 cores with both their PUs: a core is never split
        std::set<int> cores;
        for (int c : s.cpus) cores.insert(t.find_pu(c)->core);
        EXPECT_EQ(cores.size(), 2u);
        EXPECT_EQ(node_of(t, s.cpus).size(), 1u) << "a run of cores in hwloc's order stays on one node here";
        for (int c : s.cpus) EXPECT_TRUE(seen.insert(c).second);
    }
    EXPECT_EQ(seen.size(), 16u);
    // 3 ranks on 8 cores: runs of 2, 3, 3 cores (as equal as they can be), all cores given
    int total = 0;
    for (int r = 0; r < 3; ++r) total += static_cast<int>(share_of(t, 3, r).cpus.size());
    EXPECT_EQ(total, 16);
    EXPECT_EQ(share_of(t, 3, 0).cpus.size(), 4u);
    EXPECT_EQ(share_of(t, 3, 2).cpus.size(), 6u);
    // one rank alone gets the whole host
    EXPECT_EQ(share_of(t, 1, 0).cpus.size(), 16u);
}

TEST(RankShare, MoreRanksThanCoresIsRefused) {
    const Topology t = synthetic("pack:1 numa:1 core:2 pu:2");
    EXPECT_EQ(share_of(t, 2, 1).cpus.size(), 2u);
    try {
        share_of(t, 3, 0);
        FAIL() << "3 ranks on 2 cores were given CPUs";
    } catch (const UsageError& e) {
        EXPECT_NE(std::string(e.what()).find("3 ranks were started on one host with 2 core(s)"), std::string::npos)
            << e.what();
    }
    EXPECT_THROW(share_of(t, 2, 2), std::logic_error);
}

TEST(RankShare, OverlapIsFoundAndNamed) {
    std::string clash;
    EXPECT_TRUE(disjoint_sets({{0, 1}, {2, 3}, {}}, {0, 1, 2}, clash));
    EXPECT_FALSE(disjoint_sets({{0, 1}, {2, 3}, {3, 4}}, {4, 5, 7}, clash));
    EXPECT_EQ(clash, "rank 5 and rank 7 both have CPU 3");
}
