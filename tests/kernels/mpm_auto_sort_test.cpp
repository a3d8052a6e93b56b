// --sort-every=auto (mpm.hpp, OrderTracker): a reordering when the order has decayed past the
// threshold, read from the particles' elements alone, so that two runs (on any number of
// threads) reorder after the same steps; each reordering logged with its cause; fixed K kept.
#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "harness/common/units.hpp"
#include "kernels/mpm/mpm.hpp"
#include "tests/kernels/mpm_test_helpers.hpp"

using namespace suite;
using namespace suite::mpm;
using suite::mpm::testing::Team;

namespace {

mpm::Setup dam_break(const std::string& particles, int sort_every, double threshold = default_sort_threshold) {
    mpm::Setup s;
    s.mesh = "box:8,8,8";
    s.settings = case_settings("dam-break");
    s.particles = particles;
    s.sort_every = sort_every;
    s.sort_threshold = threshold;
    return s;
}

std::vector<std::uint64_t> steps_of(const State& st, ReorderCause cause) {
    std::vector<std::uint64_t> out;
    for (const Reordering& r : st.order.log)
        if (r.cause == cause) out.push_back(r.step);
    return out;
}

}  // namespace

TEST(MpmAutoSort, IsTheDefaultOfASetup) { EXPECT_EQ(mpm::Setup{}.sort_every, sort_auto); }

TEST(MpmAutoSort, SameElementShareCountsNeighboursInOneElement) {
    Team team(1);
    State st = build(dam_break("sorted", sort_auto));
    const Locality l = locality(st);
    EXPECT_DOUBLE_EQ(same_element_share(st.particles), l.same_element);
    // Sorted, 4 particles an element: 3 of every 4 neighbours share one.
    EXPECT_NEAR(l.same_element, 0.75, 0.01);
}

TEST(MpmAutoSort, ReordersWhenTheDecayReachesTheThresholdAndNotBefore) {
    Team team(1);
    const mpm::Setup s = dam_break("sorted", sort_auto, 0.2);
    State st = build(s);
    ASSERT_EQ(st.order.log.size(), 1u);
    EXPECT_EQ(st.order.log[0].cause, ReorderCause::start);
    for (int k = 0; k < 300; ++k) {
        const std::uint64_t before = st.order.count;
        advance(st, s);
        // Not reordered: the decay is still short of the threshold.
        if (st.order.count == before) {
            EXPECT_LT(st.order.decay, s.sort_threshold) << "after step " << st.steps;
        }
    }
    const std::vector<std::uint64_t> decayed = steps_of(st, ReorderCause::decayed);
    ASSERT_GE(decayed.size(), 2u) << "the water mixes: the order decays more than once in 300 steps";
    for (const Reordering& r : st.order.log) {
        if (r.cause != ReorderCause::decayed) continue;
        EXPECT_GE(r.decay, s.sort_threshold) << "after step " << r.step;
        EXPECT_GT(r.same_after, r.same_before) << "after step " << r.step;
    }
    EXPECT_EQ(st.order.count, st.order.log.size());
    EXPECT_TRUE(steps_of(st, ReorderCause::every).empty());
}

TEST(MpmAutoSort, TheDecayIsTheSumOfTheFallsSinceTheLastReordering) {
    Team team(1);
    const mpm::Setup s = dam_break("dynamic", sort_auto, 1e9);  // never due
    State st = build(s);
    const double fresh = st.order.fresh;
    double sum = 0;
    for (int k = 0; k < 60; ++k) {
        advance(st, s);
        sum += std::max(0.0, fresh - same_element_share(st.particles));
    }
    EXPECT_EQ(st.order.count, 1u);
    EXPECT_DOUBLE_EQ(st.order.decay, sum);
    EXPECT_GT(sum, 0) << "60 steps of the dam break move particles between elements";
}

TEST(MpmAutoSort, ALargerThresholdReordersLessOften) {
    Team team(1);
    const mpm::Setup often = dam_break("sorted", sort_auto, 0.1), rarely = dam_break("sorted", sort_auto, 2);
    State a = build(often), b = build(rarely);
    for (int k = 0; k < 300; ++k) advance(a, often), advance(b, rarely);
    EXPECT_GT(a.order.count, b.order.count);
    EXPECT_GE(b.order.count, 2u);
}

TEST(MpmAutoSort, TwoRunsOnAnyTeamReorderAfterTheSameSteps) {
    std::vector<std::uint64_t> steps[2];
    double x[2] = {0, 0};
    for (int t : {1, 2}) {
        Team team(t);
        mpm::Setup s = dam_break("dynamic", sort_auto, 0.2);
        s.threads = t;
        s.strategy = t > 1 ? Strategy::partition : Strategy::serial;
        State st = build(s);
        for (int k = 0; k < 200; ++k) advance(st, s);
        steps[t - 1] = steps_of(st, ReorderCause::decayed);
        x[t - 1] = suite::mpm::testing::mass_in_id_order(st.particles);
    }
    EXPECT_FALSE(steps[0].empty());
    EXPECT_EQ(steps[0], steps[1]);
    EXPECT_EQ(x[0], x[1]);
}

TEST(MpmAutoSort, FixedKStaysEveryKSteps) {
    Team team(1);
    const mpm::Setup s = dam_break("sorted", 7);
    State st = build(s);
    for (int k = 0; k < 30; ++k) advance(st, s);
    EXPECT_EQ(steps_of(st, ReorderCause::every), (std::vector<std::uint64_t>{7, 14, 21, 28}));
    EXPECT_TRUE(steps_of(st, ReorderCause::decayed).empty());
}

TEST(MpmAutoSort, SeededAndShuffledNeverReorder) {
    Team team(1);
    for (const char* order : {"seeded", "shuffled"}) {
        const mpm::Setup s = dam_break(order, sort_auto, 1e-6);
        State st = build(s);
        for (int k = 0; k < 20; ++k) advance(st, s);
        EXPECT_EQ(st.order.count, 0u) << order;
    }
}

TEST(MpmAutoSort, ABadThresholdIsRefused) {
    for (double bad : {0.0, -1.0, 2e9}) {
        const mpm::Setup s = dam_break("sorted", sort_auto, bad);
        EXPECT_THROW(build(s), UsageError) << bad;
    }
}

// dynamic under auto: every reordering the decay calls for sorts; it renumbers the grid too only
// where the share of particles outside the last renumbering's elements has reached renumber_share.
TEST(MpmAutoSort, DynamicRenumbersOnlyWhereTheParticlesHaveLeftTheRenumberedElements) {
    Team team(1);
    mpm::Setup s = dam_break("dynamic", sort_auto, 0.2);
    s.renumber_share = 0.1;
    State st = build(s);
    ASSERT_EQ(st.order.log.size(), 1u);
    EXPECT_TRUE(st.order.log[0].renumbered) << "the start renumbers";
    EXPECT_EQ(st.order.renumberings, 1u);
    for (int k = 0; k < 300; ++k) {
        const std::uint64_t before = st.order.count;
        const std::vector<std::uint32_t> curve = st.grid.curve;
        const std::uint32_t prefix = st.order.prefix;
        advance(st, s);
        if (st.order.count == before) continue;
        const Reordering& r = st.order.log.back();
        ASSERT_EQ(r.cause, ReorderCause::decayed);
        // outside is the share of the particles in elements numbered from the last prefix on,
        // before the reordering: the elements a sort alone leaves as they are.
        if (!r.renumbered) {
            std::uint64_t out = 0;
            for (std::uint32_t e : st.particles.elem) out += e >= prefix ? 1 : 0;
            EXPECT_DOUBLE_EQ(r.outside, static_cast<double>(out) / static_cast<double>(st.particles.size()));
        }
        EXPECT_EQ(r.renumbered, r.outside >= s.renumber_share) << "after step " << r.step << ": " << r.outside;
        // A sort alone leaves the grid's element order as it was.
        if (r.renumbered) {
            // Right after a renumbering every particle is in its prefix.
            for (std::uint32_t e : st.particles.elem) ASSERT_LT(e, st.order.prefix);
        } else {
            EXPECT_EQ(st.grid.curve, curve) << "after step " << r.step;
        }
    }
    std::uint64_t renumbered = 0, sorted_alone = 0;
    for (const Reordering& r : st.order.log) (r.renumbered ? renumbered : sorted_alone) += 1;
    EXPECT_EQ(renumbered, st.order.renumberings);
    EXPECT_GE(renumbered, 2u) << "the water spreads over the floor: it leaves the elements of the start";
    EXPECT_GE(sorted_alone, 2u) << "and between renumberings the particles are sorted alone";
}

TEST(MpmAutoSort, DynamicAtShareZeroRenumbersAtEveryReordering) {
    Team team(1);
    mpm::Setup s = dam_break("dynamic", sort_auto, 0.2);
    s.renumber_share = 0;
    State st = build(s);
    for (int k = 0; k < 150; ++k) advance(st, s);
    ASSERT_GE(st.order.count, 3u);
    EXPECT_EQ(st.order.renumberings, st.order.count);
    const mpm::Setup every = dam_break("dynamic", 7);
    State b = build(every);
    for (int k = 0; k < 21; ++k) advance(b, every);
    EXPECT_EQ(b.order.renumberings, 4u) << "a fixed K renumbers at every reordering, the start's included";
}

TEST(MpmAutoSort, ABadRenumberShareIsRefused) {
    for (double bad : {-0.1, 1.5}) {
        mpm::Setup s = dam_break("dynamic", sort_auto);
        s.renumber_share = bad;
        EXPECT_THROW(build(s), UsageError) << bad;
    }
}
