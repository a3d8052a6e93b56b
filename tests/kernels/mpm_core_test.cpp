// The MPM core on small grids: the shape functions, the face neighbours, the walk, the
// reorderings (particle sort, active renumbering, permute), P2G's sums, a free fall, and the
// flops the explicit kernels declare.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
#include <random>
#include <string>
#include <vector>

#include "harness/kernel/arena.hpp"
#include "harness/kernel/kernel.hpp"
#include "kernels/mesh/generate.hpp"
#include "kernels/mpm/mpm.hpp"
#include "kernels/sfc/encode.hpp"
#include "kernels/sfc/pipeline.hpp"
#include "tests/kernels/mpm_test_helpers.hpp"

namespace suite::mpm {
namespace {

using testing::index_by_id;
using testing::Team;

Grid box_grid(int n, const std::string& ordering) {
    return make_grid(sfc::ordered(mesh::box_mesh(n, n, n), ordering, 7, sfc::max_depth(3)));
}

// Point x in element e from the geometry alone (not the stored shape functions): λ_i is the
// volume of e with corner i moved to x, over e's volume.
std::array<double, 4> barycentric(const Grid& g, std::size_t e, const double* x) {
    const mesh::Mesh& m = g.mesh;
    double c[4][3];
    for (int i = 0; i < 4; ++i) {
        const std::uint32_t v = m.conn[4 * e + i];
        c[i][0] = m.x[v], c[i][1] = m.y[v], c[i][2] = m.z[v];
    }
    auto volume = [](const double(*p)[3]) {
        double a[3][3];
        for (int r = 0; r < 3; ++r)
            for (int k = 0; k < 3; ++k) a[r][k] = p[r + 1][k] - p[0][k];
        return a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
               a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
    };
    const double whole = volume(c);
    std::array<double, 4> l;
    for (int i = 0; i < 4; ++i) {
        double moved[4][3];
        std::copy(&c[0][0], &c[0][0] + 12, &moved[0][0]);
        std::copy(x, x + 3, moved[i]);
        l[i] = volume(moved) / whole;
    }
    return l;
}

// Every particle lies in its element with weights >= 0 that sum to 1 and reproduce it.
void expect_located(const State& st) {
    const Particles& p = st.particles;
    const mesh::Mesh& m = st.grid.mesh;
    for (std::size_t i = 0; i < p.size(); ++i) {
        const std::uint32_t* c = &m.conn[4 * static_cast<std::size_t>(p.elem[i])];
        const double* w = &p.w[4 * i];
        double sum = 0, at[3] = {0, 0, 0};
        for (int k = 0; k < 4; ++k) {
            EXPECT_GE(w[k], 0) << "particle " << p.id[i];
            sum += w[k];
            at[0] += w[k] * m.x[c[k]], at[1] += w[k] * m.y[c[k]], at[2] += w[k] * m.z[c[k]];
        }
        EXPECT_NEAR(sum, 1, 1e-14) << "particle " << p.id[i];
        EXPECT_NEAR(at[0], p.x[i], 1e-12) << "particle " << p.id[i];
        EXPECT_NEAR(at[1], p.y[i], 1e-12) << "particle " << p.id[i];
        EXPECT_NEAR(at[2], p.z[i], 1e-12) << "particle " << p.id[i];
    }
}

// Across the face opposite corner i of a lies b, which has a exactly once among its own
// neighbours; a and b share exactly the 3 other corners of a. Returns the boundary faces.
std::size_t expect_symmetric_neighbours(const Grid& g) {
    std::size_t boundary = 0;
    for (std::size_t a = 0; a < g.elements(); ++a)
        for (int i = 0; i < 4; ++i) {
            const std::int32_t b = g.neighbour[4 * a + i];
            if (b < 0) {
                ++boundary;
                continue;
            }
            EXPECT_LT(static_cast<std::size_t>(b), g.elements());
            if (static_cast<std::size_t>(b) >= g.elements()) continue;
            int back = 0, shared = 0;
            for (int j = 0; j < 4; ++j)
                back += g.neighbour[4 * static_cast<std::size_t>(b) + j] == static_cast<std::int32_t>(a) ? 1 : 0;
            EXPECT_EQ(back, 1) << "element " << a << " face " << i;
            for (int j = 0; j < 4; ++j) {
                const std::uint32_t v = g.mesh.conn[4 * a + j];
                const bool in_b = std::count(&g.mesh.conn[4 * static_cast<std::size_t>(b)],
                                             &g.mesh.conn[4 * static_cast<std::size_t>(b)] + 4, v) == 1;
                shared += in_b ? 1 : 0;
                if (j == i) {
                    EXPECT_FALSE(in_b) << "element " << a << " face " << i
                                       << ": the opposite corner is in the neighbour";
                }
            }
            EXPECT_EQ(shared, 3) << "element " << a << " face " << i;
        }
    return boundary;
}

TEST(MpmGrid, ShapeFunctionsAreOneAtTheirCornerAndZeroAtTheOthers) {
    const Grid g = make_grid(mesh::box_mesh(2, 2, 2));
    for (std::size_t e = 0; e < g.elements(); ++e)
        for (int i = 0; i < 4; ++i) {
            const std::uint32_t v = g.mesh.conn[4 * e + i];
            for (int j = 0; j < 4; ++j) {
                const double* s = &g.shape[16 * e + 4 * j];
                const double n = s[0] + s[1] * g.mesh.x[v] + s[2] * g.mesh.y[v] + s[3] * g.mesh.z[v];
                EXPECT_NEAR(n, i == j ? 1.0 : 0.0, 1e-12) << "element " << e << " corner " << i << " function " << j;
            }
        }
}

TEST(MpmGrid, ShapeFunctionsSumToOneAndTheirGradientsToZero) {
    // Σ N_i(x) = Σ a_i + (Σ g_i) · x: 1 everywhere in the element exactly when these hold,
    // which is what conserves mass (Σ w = 1) and momentum (the internal forces cancel).
    for (const char* ordering : {"natural", "random"}) {
        const Grid g = box_grid(3, ordering);
        for (std::size_t e = 0; e < g.elements(); ++e) {
            const double* s = &g.shape[16 * e];
            double gmax = 0;
            for (int i = 0; i < 4; ++i)
                for (int k = 1; k < 4; ++k) gmax = std::max(gmax, std::fabs(s[4 * i + k]));
            EXPECT_NEAR(s[0] + s[4] + s[8] + s[12], 1, 1e-12) << ordering << " element " << e;
            for (int k = 1; k < 4; ++k)
                EXPECT_NEAR(s[k] + s[4 + k] + s[8 + k] + s[12 + k], 0, 1e-14 * gmax) << ordering << " element " << e;
        }
    }
}

TEST(MpmGrid, FaceNeighboursAreSymmetricAndShareThreeCorners) {
    for (const char* ordering : {"natural", "random", "hilbert"}) {
        SCOPED_TRACE(ordering);
        const Grid g = box_grid(4, ordering);
        // The box's 6 sides, 4 x 4 squares each, 2 triangles a square.
        EXPECT_EQ(expect_symmetric_neighbours(g), 6u * 4 * 4 * 2);
    }
}

TEST(MpmLocate, WalksFromAFarElementToTheOneHoldingThePoint) {
    for (const char* ordering : {"natural", "random"}) {
        SCOPED_TRACE(ordering);
        Settings s;
        State st = make_state(box_grid(5, ordering), s, Strategy::serial, 1);
        const Grid& g = st.grid;
        std::vector<std::array<double, 3>> centre(g.elements());
        for (std::size_t e = 0; e < g.elements(); ++e) {
            centre[e] = {0, 0, 0};
            for (int i = 0; i < 4; ++i) {
                const std::uint32_t v = g.mesh.conn[4 * e + i];
                centre[e][0] += g.mesh.x[v] / 4, centre[e][1] += g.mesh.y[v] / 4, centre[e][2] += g.mesh.z[v] / 4;
            }
        }
        // Random points, and lattice points that lie on the grid's vertices, edges and faces.
        std::mt19937_64 rng(15);
        std::uniform_real_distribution<double> u(0, 1);
        std::vector<std::array<double, 3>> points;
        for (int k = 0; k < 500; ++k) points.push_back({u(rng), u(rng), u(rng)});
        for (double a : {0.0, 0.2, 0.5, 1.0}) points.push_back({a, 0.4, 0.1 + a / 2}), points.push_back({0.6, a, a});
        Particles& p = st.particles;
        p.resize(points.size());
        for (std::size_t k = 0; k < points.size(); ++k) {
            p.x[k] = points[k][0], p.y[k] = points[k][1], p.z[k] = points[k][2];
            p.id[k] = static_cast<std::uint32_t>(k);
            std::size_t far = 0;
            double d = -1;
            for (std::size_t e = 0; e < g.elements(); ++e) {
                const double de = std::hypot(centre[e][0] - p.x[k], centre[e][1] - p.y[k], centre[e][2] - p.z[k]);
                if (de > d) d = de, far = e;
            }
            p.elem[k] = static_cast<std::uint32_t>(far);
        }
        locate(st);
        expect_located(st);
        for (std::size_t k = 0; k < points.size(); ++k) {
            const std::array<double, 4> l = barycentric(g, p.elem[k], points[k].data());
            for (int i = 0; i < 4; ++i) {
                EXPECT_GE(l[i], -1e-12) << "point " << k << " is not in element " << p.elem[k];
                EXPECT_NEAR(p.w[4 * k + i], l[i], 1e-12) << "point " << k;
            }
        }
    }
}

// A small dam, some steps in, so that the stresses and velocities are not all alike.
State moving_dam(const std::string& particles) {
    mpm::Setup s;
    s.mesh = "box:6,6,6";
    s.particles = particles;
    s.sort_every = 0;
    State st = build(s);
    for (int n = 0; n < 10; ++n) advance(st, s);
    return st;
}

// Particle i of a and particle j of b carry the same state.
void expect_same_particle(const Particles& a, std::size_t i, const Particles& b, std::size_t j) {
    EXPECT_EQ(a.id[i], b.id[j]);
    EXPECT_EQ(a.x[i], b.x[j]);
    EXPECT_EQ(a.y[i], b.y[j]);
    EXPECT_EQ(a.z[i], b.z[j]);
    EXPECT_EQ(a.vz[i], b.vz[j]);
    EXPECT_EQ(a.mass[i], b.mass[j]);
    EXPECT_EQ(a.volume[i], b.volume[j]);
    for (int k = 0; k < 6; ++k) EXPECT_EQ(a.stress[k][i], b.stress[k][j]) << "component " << k;
}

TEST(MpmReorder, SortParticlesOrdersThemByElementAndKeepsEachOne) {
    Team team(1);
    State st = moving_dam("shuffled");
    const Particles before = st.particles;
    sort_particles(st);
    const Particles& p = st.particles;
    ASSERT_EQ(p.size(), before.size());
    // In the grid's element order, not along the curve: on this natural grid the two differ.
    bool curve_order = true;
    for (std::size_t i = 1; i < p.size(); ++i) {
        ASSERT_LE(p.elem[i - 1], p.elem[i]) << "at " << i;
        curve_order = curve_order && st.grid.curve[p.elem[i - 1]] <= st.grid.curve[p.elem[i]];
    }
    EXPECT_FALSE(curve_order) << "the grid's order is the curve's here: the test cannot tell the keys apart";
    std::vector<std::uint32_t> ids = p.id, old_ids = before.id;
    std::sort(ids.begin(), ids.end());
    std::sort(old_ids.begin(), old_ids.end());
    EXPECT_EQ(ids, old_ids);
    EXPECT_NE(p.id, before.id);  // the shuffled order did change
    const std::vector<std::size_t> was = index_by_id(before);
    for (std::size_t i = 0; i < p.size(); ++i) expect_same_particle(p, i, before, was[p.id[i]]);
    expect_located(st);
}

// A reordering does not locate the particles again (a permutation keeps each one's element and
// weights): what it leaves must be, bit for bit, what a locate would make of it, bins included.
TEST(MpmReorder, AReorderedStateIsWhatLocatingItAgainGives) {
    Team team(2);
    for (Strategy strategy : {Strategy::serial, Strategy::partition, Strategy::colour}) {
        const std::string where = strategy_name(strategy);
        mpm::Setup s;
        s.mesh = "box:6,6,6";
        s.particles = "shuffled";
        s.strategy = strategy;
        s.threads = 2;
        s.sort_every = 0;
        State st = build(s);
        for (int n = 0; n < 10; ++n) advance(st, s);
        std::vector<std::uint32_t> order(st.particles.size());
        for (std::size_t i = 0; i < order.size(); ++i) order[i] = static_cast<std::uint32_t>(order.size() - 1 - i);
        for (int pass = 0; pass < 2; ++pass) {
            const std::vector<std::uint32_t> bins_before = st.bins.start;
            if (pass == 0)
                reorder_particles(st, order);
            else
                sort_particles(st);
            State again = st;
            locate(again);
            const std::string what = where + (pass == 0 ? ", reversed" : ", sorted");
            EXPECT_EQ(st.particles.elem, again.particles.elem) << what;
            EXPECT_EQ(st.particles.w, again.particles.w) << what;
            EXPECT_EQ(st.node_hi, again.node_hi) << what;
            EXPECT_EQ(st.bins.start, again.bins.start) << what;
            EXPECT_EQ(st.bins.start, bins_before) << what << ": the elements' counts changed";
            ASSERT_EQ(st.bins.order.size(), again.bins.order.size()) << what;
            EXPECT_TRUE(std::equal(st.bins.order.begin(), st.bins.order.end(), again.bins.order.begin())) << what;
            if (strategy != Strategy::serial) {
                // The bins follow the new order: particle bins.order[k] lies in the element whose range holds k.
                for (std::size_t e = 0; e + 1 < st.bins.start.size(); ++e)
                    for (std::uint32_t k = st.bins.start[e]; k < st.bins.start[e + 1]; ++k)
                        ASSERT_EQ(st.particles.elem[st.bins.order[k]], e) << what << ", slot " << k;
            } else {
                EXPECT_TRUE(st.bins.start.empty()) << what << ": the serial scatter keeps no bins";
            }
        }
    }
}

TEST(MpmReorder, RenumberActivePutsTheOccupiedElementsFirst) {
    Team team(1);
    State st = moving_dam("shuffled");
    const Particles before = st.particles;
    const std::size_t elements = st.grid.elements(), nodes = st.grid.nodes();
    renumber_active(st);
    const Particles& p = st.particles;
    ASSERT_EQ(st.grid.elements(), elements);
    ASSERT_EQ(st.grid.nodes(), nodes);
    std::vector<char> occupied(elements, 0);
    for (std::uint32_t e : p.elem) occupied[e] = 1;
    const std::size_t active = static_cast<std::size_t>(std::count(occupied.begin(), occupied.end(), 1));
    EXPECT_LT(active, elements);
    for (std::size_t e = 0; e < elements; ++e) EXPECT_EQ(occupied[e], e < active ? 1 : 0) << "element " << e;
    for (std::size_t e = 1; e < active; ++e) EXPECT_LT(st.grid.curve[e - 1], st.grid.curve[e]);
    // Nodes by first touch: the occupied elements use the lowest numbers.
    std::uint32_t highest = 0;
    std::vector<char> used(nodes, 0);
    for (std::size_t k = 0; k < 4 * active; ++k)
        highest = std::max(highest, st.grid.mesh.conn[k]), used[st.grid.mesh.conn[k]] = 1;
    EXPECT_EQ(highest + 1u, static_cast<std::uint32_t>(std::count(used.begin(), used.end(), 1)));
    EXPECT_EQ(p.id, before.id);  // particles stay where they were stored
    for (std::size_t i = 0; i < p.size(); ++i) expect_same_particle(p, i, before, i);
    expect_located(st);
    expect_symmetric_neighbours(st.grid);
}

TEST(MpmReorder, PermuteLeavesTheNextStepUnchanged) {
    Team team(1);
    State a = moving_dam("sorted");
    State b = a;
    std::vector<std::uint32_t> perm(a.grid.elements()), new_id(a.grid.nodes());
    std::iota(perm.begin(), perm.end(), 0u);
    std::iota(new_id.begin(), new_id.end(), 0u);
    std::mt19937_64 rng(3);
    std::shuffle(perm.begin(), perm.end(), rng);
    std::shuffle(new_id.begin(), new_id.end(), rng);
    permute(b, perm, new_id);
    expect_located(b);
    expect_symmetric_neighbours(b.grid);
    EXPECT_NE(a.particles.elem, b.particles.elem);
    step(a);
    step(b);
    EXPECT_LE(testing::max_position_difference(a.particles, b.particles), 1e-14);  // measured: 0
    for (std::size_t i = 0; i < a.particles.size(); ++i)
        for (int k = 0; k < 6; ++k)
            EXPECT_NEAR(a.particles.stress[k][i], b.particles.stress[k][i], 1e-9) << "particle " << i;
}

TEST(MpmP2G, NodalMassAndMomentumSumToTheParticles) {
    Team team(2);
    for (Strategy strategy : {Strategy::serial, Strategy::atomic, Strategy::colour, Strategy::partition}) {
        SCOPED_TRACE(strategy_name(strategy));
        mpm::Setup s;
        s.mesh = "box:6,6,6";
        s.strategy = strategy;
        s.threads = 2;
        State st = build(s);
        for (int n = 0; n < 5; ++n) advance(st, s);
        p2g(st);
        const Totals t = totals(st.particles);
        double m = 0, q[3] = {0, 0, 0};
        for (const NodeState& n : st.nodes) {
            m += n.m;
            for (int k = 0; k < 3; ++k) q[k] += n.p[k];
        }
        EXPECT_NEAR(m, t.mass, 1e-12 * t.mass);
        const double scale = std::fabs(t.momentum[0]) + std::fabs(t.momentum[1]) + std::fabs(t.momentum[2]);
        EXPECT_GT(scale, 0);
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(q[k], t.momentum[k], 1e-12 * scale) << "axis " << k;
    }
}

TEST(MpmFreeFall, VelocityIsGTimesTAwayFromTheWalls) {
    Settings s;
    s.region = {{0.35, 0.35, 0.6}, {0.65, 0.65, 0.9}};
    State st = make_state(make_grid(mesh::box_mesh(8, 8, 8)), s, Strategy::serial, 1);
    const double m0 = totals(st.particles).mass;
    for (int k = 0; k < 20; ++k) step(st);
    const double v = s.gravity[2] * st.time;
    for (std::size_t p = 0; p < st.particles.size(); ++p) {
        EXPECT_NEAR(st.particles.vz[p], v, 1e-12 * std::fabs(v));
        EXPECT_NEAR(st.particles.vx[p], 0, 1e-12);
    }
    EXPECT_DOUBLE_EQ(totals(st.particles).mass, m0);
}

// The hand counts of mpm_kernels.cpp, pinned: a change to the loops that changes them changes
// these numbers too. A step's count depends on the material (dam-break is the fluid); `suite
// list` documents the default case's.
TEST(MpmKernelWork, EveryPhaseDeclaresItsCountedFlopsAParticle) {
    Team team(1);
    const struct {
        const char* kernel;
        const char* variant;
        const char* the_case;  // --case: dam-collapse (elastic, the default), dam-break (fluid)
        double flops;          // a particle (a particle-step)
    } points[] = {{"mpm-p2g", "serial", "dam-collapse", 159},
                  {"mpm-g2p", "seeded", "dam-collapse", 64},
                  {"mpm-step", "seeded", "dam-collapse", 583},
                  {"mpm-step", "seeded", "dam-break", 446}};
    for (const auto& pt : points) {
        const std::string where = std::string(pt.kernel) + " --case=" + pt.the_case;
        const KernelEntry* k = find_kernel(pt.kernel);
        ASSERT_NE(k, nullptr) << where;
        KernelConfig cfg;
        cfg.access = {"natural", 0};
        cfg.variant = pt.variant;
        cfg.size = k->test_size;
        cfg.params = default_params(k->info);
        cfg.params["case"] = std::string(pt.the_case);
        cfg.params["warm-steps"] = 1.0;
        k->validate(cfg);
        Arena arena(MemoryPolicy{});
        auto kernel = k->make(cfg);
        kernel->setup(arena);
        const Work w = kernel->work();
        ASSERT_GT(w.units, 0) << where;
        EXPECT_GT(w.flops, 0) << where;
        EXPECT_DOUBLE_EQ(w.flops / w.units, pt.flops) << where;
        if (default_params(k->info).at("case") == ParamValue(pt.the_case))
            EXPECT_DOUBLE_EQ(k->info.flops_per_unit, pt.flops) << where;
        else
            EXPECT_NE(k->info.flops_per_unit, pt.flops) << where << ": the fluid's step is not the default case's";
    }
}

}  // namespace
}  // namespace suite::mpm
