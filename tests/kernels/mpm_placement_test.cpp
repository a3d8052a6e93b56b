// The MPM kernels' arrays in the harness's arena: every particle array, the nodes and the element
// volume sums placed, first touched by the computing threads and observed in the record; the
// reorderings (sort_particles, renumber_active, a shuffle) write back into the same pages; a
// state built with an arena computes bit for bit what one built without computes; --placement
// other than local is accepted for mpm-p2g, mpm-g2p and mpm-step (and still refused for a
// kernel whose arrays are heap memory).
#include <gtest/gtest.h>

#include <algorithm>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "harness/common/units.hpp"
#include "harness/kernel/arena.hpp"
#include "harness/machine/placement.hpp"
#include "harness/machine/topology.hpp"
#include "harness/measure/plan.hpp"
#include "harness/measure/runner.hpp"
#include "kernels/mpm/mpm.hpp"
#include "tests/kernels/mpm_test_helpers.hpp"
#include "tests/process.hpp"
#include "tests/synthetic_topology.hpp"

// GCC 12 at -O3 says the std::string of a Point built inside these loops "may be used
// uninitialized" (a false alarm of its inlining of the aggregate: every string is set, and no
// way of writing the aggregate here avoids it). With -Werror in CI, it is silenced for this file.
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"

using namespace suite;
using namespace suite::mpm;
using suite::mpm::testing::Team;

namespace {

// What every MPM kernel puts in its arena, in order (the kernels integrate the stress in the
// mixed way, so the element volume sums are there too); with `bins` (the colour and partition
// strategies), the bins' particle order.
std::vector<std::string> expected_arrays(bool bins) {
    std::vector<std::string> names(std::begin(particle_array_names), std::end(particle_array_names));
    names.emplace_back("reorder-scratch");
    if (bins) names.emplace_back("bins-order");
    for (const char* n : {"nodes", "element-volume"}) names.emplace_back(n);
    return names;
}

std::vector<std::string> names_of(const std::vector<ArrayPlacement>& pages) {
    std::vector<std::string> out;
    for (const auto& a : pages) out.push_back(a.name);
    return out;
}

// Every page of every array present, counted on a node the machine has; on a one-node machine,
// all of them on that node.
void expect_all_present(const std::vector<ArrayPlacement>& pages, const Topology& topo, const std::string& where) {
    for (const auto& a : pages) {
        EXPECT_EQ(a.pages_not_present, 0u) << where << ": array " << a.name << " " << a.error;
        std::uint64_t counted = 0;
        for (const auto& [node, count] : a.pages_per_node) {
            EXPECT_NE(topo.find_node(node), nullptr)
                << where << ": array " << a.name << " has pages on unknown node " << node;
            counted += count;
        }
        EXPECT_EQ(counted, a.pages) << where << ": array " << a.name;
        if (topo.nodes.size() == 1) {
            const auto on = a.pages_per_node.find(topo.nodes[0].os_index);
            EXPECT_EQ(on == a.pages_per_node.end() ? 0 : on->second, a.pages) << where << ": array " << a.name;
        }
    }
}

int two_or_one(const Topology& topo) { return std::min(2, topo.pu_count()); }

// Every array of a state, as the bytes to compare.
void expect_same_state(const State& a, const State& b, const std::string& where) {
    const Particles& p = a.particles;
    const Particles& q = b.particles;
    ASSERT_EQ(p.size(), q.size()) << where;
    EXPECT_EQ(p.x, q.x) << where;
    EXPECT_EQ(p.y, q.y) << where;
    EXPECT_EQ(p.z, q.z) << where;
    EXPECT_EQ(p.vx, q.vx) << where;
    EXPECT_EQ(p.vy, q.vy) << where;
    EXPECT_EQ(p.vz, q.vz) << where;
    EXPECT_EQ(p.mass, q.mass) << where;
    EXPECT_EQ(p.volume, q.volume) << where;
    for (int k = 0; k < 6; ++k) EXPECT_EQ(p.stress[k], q.stress[k]) << where << ": stress " << k;
    EXPECT_EQ(p.w, q.w) << where;
    EXPECT_EQ(p.elem, q.elem) << where;
    EXPECT_EQ(p.id, q.id) << where;
    EXPECT_EQ(a.bins.order, b.bins.order) << where;
    ASSERT_EQ(a.node_hi, b.node_hi) << where;
    for (std::uint32_t n = 0; n < a.node_hi; ++n) {
        const NodeState& s = a.nodes[n];
        const NodeState& t = b.nodes[n];
        const bool same = s.m == t.m && std::equal(s.p, s.p + 3, t.p) && std::equal(s.f, s.f + 3, t.f);
        if (!same) {
            ADD_FAILURE() << where << ": node " << n << " differs";
            break;
        }
    }
    EXPECT_EQ(a.grid.mesh.conn, b.grid.mesh.conn) << where;
    EXPECT_EQ(a.time, b.time) << where;
}

// The data pointers of the placed arrays: the reorderings must keep every one.
std::vector<const void*> pointers(const State& st) {
    const Particles& p = st.particles;
    std::vector<const void*> out = {
        p.x.data(),  p.y.data(),           p.z.data(),           p.vx.data(),     p.vy.data(),
        p.vz.data(), p.mass.data(),        p.volume.data(),      p.w.data(),      p.elem.data(),
        p.id.data(), p.scratch.buf.data(), st.bins.order.data(), st.nodes.data(), st.element_volume.data()};
    for (const auto& s : p.stress) out.push_back(s.data());
    return out;
}

mpm::Setup small(const std::string& particles, Strategy strategy, int threads, Integration integration) {
    mpm::Setup s;
    s.mesh = "box:6,6,6";
    s.ordering = "hilbert";
    s.particles = particles;
    s.sort_every = 1;  // a reordering after every step
    s.strategy = strategy;
    s.threads = threads;
    s.settings.integration = integration;
    return s;
}

}  // namespace

TEST(MpmPlacement, EveryKernelRecordsEachArrayWithItsPagesPresent) {
    const Topology topo = Topology::load();
    RunSettings s;
    s.pin = parse_pin("compact", topo);
    s.placement = parse_placement("local", topo);
    s.reps = 2;
    const int threads = two_or_one(topo);
    const struct {
        const char* kernel;
        const char* variant;
    } points[] = {{"mpm-p2g", "partition"},
                  {"mpm-p2g", "atomic"},
                  {"mpm-g2p", "shuffled"},
                  {"mpm-step", "dynamic"},
                  {"mpm-step", "sorted"}};
    for (const auto& pt : points) {
        const KernelEntry* k = find_kernel(pt.kernel);
        ASSERT_NE(k, nullptr) << pt.kernel;
        EXPECT_FALSE(k->info.heap_arrays) << pt.kernel << ": its arrays are the arena's now";
        const std::string where = std::string(pt.kernel) + " " + pt.variant;
        const Record r = run_point({k, {"hilbert", 0}, pt.variant, k->test_size, threads}, s, topo);
        EXPECT_TRUE(r.verification.passed) << where << ": " << r.verification.detail;
        // mpm-g2p and mpm-step scatter with the partition strategy on more than one thread.
        const std::string variant = pt.variant;
        const bool bins =
            variant == "partition" || variant == "colour" || (std::string(pt.kernel) != "mpm-p2g" && threads > 1);
        EXPECT_EQ(names_of(r.pages), expected_arrays(bins)) << where;
        expect_all_present(r.pages, topo, where);
        // The particle arrays' lengths: x is 8 B per particle, w 32 B, elem 4 B.
        const double particles = r.facts.empty() ? 0 : r.facts.front().value;
        ASSERT_GT(particles, 0) << where;
        for (const auto& a : r.pages) {
            const double per = a.name == "w" || a.name == "reorder-scratch"                   ? 32
                               : a.name == "elem" || a.name == "id" || a.name == "bins-order" ? 4
                                                                                              : 8;
            if (a.name == "nodes" || a.name == "element-volume") continue;
            EXPECT_GE(static_cast<double>(a.bytes), per * particles) << where << ": " << a.name;
            EXPECT_LT(static_cast<double>(a.bytes), per * particles + 4096) << where << ": " << a.name;
        }
    }
}

TEST(MpmPlacement, TheImplicitKernelsPlaceTheAccelerationsAndTheSolveItsWholeSystem) {
    const Topology topo = Topology::load();
    RunSettings s;
    s.pin = parse_pin("compact", topo);
    s.placement = parse_placement("local", topo);
    s.reps = 2;
    const int threads = two_or_one(topo);
    for (const char* kernel : {"mpm-implicit-solve", "mpm-implicit-step"}) {
        const KernelEntry* k = find_kernel(kernel);
        ASSERT_NE(k, nullptr) << kernel;
        const Record r = run_point({k, {"hilbert", 0}, "seeded", k->test_size, threads}, s, topo);
        ASSERT_TRUE(r.verification.passed) << kernel << ": " << r.verification.detail;
        expect_all_present(r.pages, topo, kernel);
        const std::vector<std::string> names = names_of(r.pages);
        for (const char* a : {"x", "stress-zx", "ax", "ay", "az", "nodes", "element-volume"})
            EXPECT_NE(std::find(names.begin(), names.end(), a), names.end()) << kernel << " lacks " << a;
        double nnz = 0, rows = 0;
        for (const auto& f : r.facts) {
            if (f.name == "nonzeros") nnz = f.value;
            if (f.name == "rows") rows = f.value;
        }
        ASSERT_GT(nnz, 0);
        const bool solve = std::string(kernel) == "mpm-implicit-solve";
        for (const auto& a : r.pages) {
            // The solve's matrix and vectors at their lengths; the step keeps its system on the heap.
            const double expected = a.name == "system-val"        ? 8 * nnz
                                    : a.name == "system-col"      ? 4 * nnz
                                    : a.name == "system-row-ptr"  ? 4 * (rows + 1)
                                    : a.name.rfind("cg-", 0) == 0 ? 8 * rows
                                                                  : -1;
            if (expected < 0) continue;
            EXPECT_TRUE(solve) << kernel << " places " << a.name;
            EXPECT_GE(static_cast<double>(a.bytes), expected) << a.name;
            EXPECT_LT(static_cast<double>(a.bytes), expected + 4096) << a.name;
        }
        const int system_arrays = static_cast<int>(std::count_if(names.begin(), names.end(), [](const std::string& n) {
            return n.rfind("system-", 0) == 0 || n.rfind("cg-", 0) == 0;
        }));
        EXPECT_EQ(system_arrays, solve ? 10 : 0) << kernel;
    }
}

TEST(MpmPlacement, ReorderingsKeepTheArenaPagesAndMatchTheHeapStateBitForBit) {
    const Topology topo = Topology::load();
    // One thread with mixed integration (its element volume sums are atomic adds, whose order
    // more threads would not fix); two with particle integration and the partition scatter,
    // which adds in the same order every time.
    struct Case {
        int threads;
        Strategy strategy;
        Integration integration;
        const char* particles;
    };
    const Case cases[] = {{1, Strategy::serial, Integration::mixed, "dynamic"},
                          {two_or_one(topo), Strategy::partition, Integration::particle, "dynamic"},
                          {two_or_one(topo), Strategy::partition, Integration::particle, "shuffled"}};
    for (const Case& c : cases) {
        const std::string where =
            std::to_string(c.threads) + " thread(s), " + strategy_name(c.strategy) + ", " + c.particles;
        Team team(c.threads);
        const mpm::Setup setup = small(c.particles, c.strategy, c.threads, c.integration);
        Arena arena(MemoryPolicy{});
        State placed = build(setup, &arena);
        State heap = build(setup);
        ASSERT_TRUE(placed.particles.placed()) << where;
        ASSERT_TRUE(placed.nodes.placed()) << where;
        EXPECT_EQ(placed.bins.order.placed(), c.strategy == Strategy::partition) << where;
        EXPECT_FALSE(heap.particles.placed()) << where;
        EXPECT_FALSE(heap.nodes.placed()) << where;
        const std::vector<const void*> before = pointers(placed);
        const std::vector<std::string> names = names_of(arena.observe());
        expect_same_state(placed, heap, where + ", built");
        for (int k = 0; k < 4; ++k) {
            advance(placed, setup);
            advance(heap, setup);
        }
        // Beyond the schedule: a shuffle through reorder_particles, a renumbering, a sort.
        std::vector<std::uint32_t> order(placed.particles.size());
        for (std::size_t i = 0; i < order.size(); ++i) order[i] = static_cast<std::uint32_t>((i * 7919) % order.size());
        if (std::set<std::uint32_t>(order.begin(), order.end()).size() == order.size()) {
            reorder_particles(placed, order);
            reorder_particles(heap, order);
        }
        renumber_active(placed);
        renumber_active(heap);
        sort_particles(placed);
        sort_particles(heap);
        for (int k = 0; k < 2; ++k) {
            advance(placed, setup);
            advance(heap, setup);
        }
        EXPECT_EQ(pointers(placed), before) << where << ": a reordering replaced a placed array";
        EXPECT_TRUE(placed.particles.placed()) << where;
        EXPECT_TRUE(placed.nodes.placed()) << where;
        const std::vector<ArrayPlacement> after = arena.observe();
        EXPECT_EQ(names_of(after), names) << where << ": the reorderings allocated in the arena";
        expect_all_present(after, topo, where);
        expect_same_state(placed, heap, where + ", after 6 steps and reorderings");
        // A copy is the copy's own memory, with the same values; assigned back, the values go
        // into the placed pages.
        State copy = placed;
        EXPECT_FALSE(copy.particles.placed()) << where;
        EXPECT_FALSE(copy.nodes.placed()) << where;
        expect_same_state(copy, placed, where + ", a copy");
        advance(copy, setup);
        placed.particles = copy.particles;
        EXPECT_EQ(pointers(placed), before) << where;
        EXPECT_EQ(placed.particles.x, copy.particles.x) << where;
    }
}

TEST(MpmPlacement, TheCommandLineTakesEveryPlacementForTheMpmKernels) {
    const Topology topo = Topology::load();
    const int node = topo.nodes.at(0).os_index;
    std::vector<std::string> placements = {"node:" + std::to_string(node), "interleave"};
    if (topo.nodes.size() >= 2) placements.push_back("remote");
    for (const std::string& placement : placements) {
        suite::test::TempDir tmp;
        const std::string out = tmp.file("r.json");
        const std::vector<std::string> args = {"--kernel=mpm-step,mpm-g2p",
                                               "--particles=dynamic",
                                               "--mesh=box:4,4,4",
                                               "--threads=1",
                                               "--reps=2",
                                               "--placement=" + placement,
                                               "--quiet",
                                               "--out=" + out};
        const suite::test::Outcome r = suite::test::run_suite(args, 120);
        ASSERT_EQ(r.status, 0) << suite::test::join(args) << "\n" << suite::test::describe(r);
        const nlohmann::json doc = nlohmann::json::parse(suite::test::slurp(out));
        ASSERT_EQ(doc["results"].size(), 2u) << placement;
        for (const auto& rec : doc["results"]) {
            const std::string where = rec["kernel"].get<std::string>() + " --placement=" + placement;
            EXPECT_TRUE(rec["verification"]["passed"].get<bool>()) << where;
            EXPECT_EQ(rec["placement"]["requested"], placement) << where << "\n" << rec["placement"].dump(1);
            std::vector<std::string> names;
            for (const auto& a : rec["placement"]["arrays"]) {
                names.push_back(a["array"]);
                EXPECT_EQ(a["pages_not_present"], 0) << where << ": " << a.dump();
                std::uint64_t sum = 0;
                for (const auto& [n, count] : a["pages_per_node"].items()) sum += count.get<std::uint64_t>();
                EXPECT_EQ(sum, a["pages"].get<std::uint64_t>()) << where << ": " << a.dump();
                // Bound to one node: every page there.
                if (placement.rfind("node:", 0) == 0) {
                    EXPECT_EQ(a["pages_per_node"][std::to_string(node)], a["pages"]) << where << ": " << a.dump();
                }
            }
            EXPECT_EQ(names, expected_arrays(false)) << where << " (one thread: the serial scatter, no bins)";
        }
        const suite::test::Outcome valid = suite::test::validate_against_schema(out);
        EXPECT_EQ(valid.status, 0) << suite::test::describe(valid);
    }
    // A dry run takes it too.
    const suite::test::Outcome dry = suite::test::run_suite(
        {"--kernel=mpm-p2g,mpm-g2p,mpm-step", "--mesh=box:4,4,4", "--placement=interleave", "--dry-run"}, 60);
    EXPECT_EQ(dry.status, 0) << suite::test::describe(dry);
    // One NUMA node: remote is refused as for every kernel (no node is remote), not for the MPM
    // kernels' sake.
    if (topo.nodes.size() == 1) {
        const suite::test::Outcome remote =
            suite::test::run_suite({"--kernel=mpm-step", "--mesh=box:4,4,4", "--placement=remote", "--dry-run"}, 60);
        EXPECT_EQ(remote.status, 2) << suite::test::describe(remote);
        EXPECT_NE(remote.err.find("at least 2 NUMA nodes"), std::string::npos) << remote.err;
        EXPECT_EQ(remote.err.find("heap memory"), std::string::npos) << remote.err;
    }
}

TEST(MpmPlacement, PlanningTakesRemoteAndInterleaveForTheMpmKernelsOnTwoSockets) {
    // A synthetic two-socket machine: what this one-node VM cannot show.
    const Topology t = suite::testing::two_socket();
    for (const char* placement : {"remote", "interleave", "node:1"}) {
        RunOptions o;
        o.kernels = "mpm-p2g,mpm-g2p,mpm-step";
        o.mesh = "box:4,4,4";
        o.threads = "1";
        o.placement = placement;
        try {
            const Plan plan = make_plan(o, t);
            EXPECT_FALSE(plan.points.empty()) << placement;
        } catch (const UsageError& e) {
            ADD_FAILURE() << "--placement=" << placement << " refused: " << e.what();
        }
    }
}

namespace {

// A kernel whose array is plain heap memory: the harness must still refuse to "place" it.
class HeapKernel final : public Kernel {
public:
    explicit HeapKernel(const KernelConfig& cfg) : n_(std::max<std::uint64_t>(cfg.size / sizeof(double), 1)) {}
    void setup(Arena&) override { v_.assign(n_, 1.0); }
    void run(int calls) override {
        for (int c = 0; c < calls; ++c)
            for (double& x : v_) x += 1;
        calls_ += calls;
    }
    Verification verify() override {
        Verification v;
        // The registry walk runs it too, and expects a kernel that never ran to fail.
        v.passed = calls_ > 0 &&
                   std::all_of(v_.begin(), v_.end(), [&](double x) { return x == 1.0 + static_cast<double>(calls_); });
        v.detail = calls_ > 0 ? "every element 1 + calls" : "no repetition ran";
        return v;
    }
    Work work() const override {
        return {static_cast<double>(n_), 16.0 * static_cast<double>(n_), 24.0 * static_cast<double>(n_), 0, n_ * 8};
    }

private:
    std::uint64_t n_;
    std::vector<double> v_;
    long calls_ = 0;
};

const bool heap_kernel_registered = [] {
    KernelEntry e;
    e.info.name = "test-heap-arrays";
    e.info.group = "test";
    e.info.formula = "a[i] += 1";
    e.info.unit = "element";
    e.info.accesses = {"sequential"};
    e.info.heap_arrays = true;
    e.make = [](const KernelConfig& c) { return std::make_unique<HeapKernel>(c); };
    e.test_size = 64 << 10;
    return register_kernel(std::move(e));
}();

}  // namespace

TEST(MpmPlacement, AKernelWithHeapArraysIsStillRefusedAPlacement) {
    ASSERT_TRUE(heap_kernel_registered);
    const Topology t = suite::testing::two_socket();
    RunOptions o;
    o.kernels = "test-heap-arrays";
    o.size = "64KiB";
    o.threads = "1";
    o.placement = "local";
    EXPECT_EQ(make_plan(o, t).points.size(), 1u);
    for (const char* placement : {"remote", "interleave", "node:1"}) {
        o.placement = placement;
        try {
            make_plan(o, t);
            ADD_FAILURE() << "--placement=" << placement << " was accepted for a kernel whose arrays are heap memory";
        } catch (const UsageError& e) {
            const std::string what = e.what();
            EXPECT_NE(what.find("test-heap-arrays"), std::string::npos) << what;
            EXPECT_NE(what.find("heap memory"), std::string::npos) << what;
        }
    }
}
