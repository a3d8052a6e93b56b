// The physics of the MPM step (issue 15): mass, free fall, momentum against gravity and the
// walls' reactions, the stress update against a linear velocity field, a confined column
// against the 1D bar's exact solution, the dam collapse over 1000 steps, and bad settings.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <string>

#include "harness/common/units.hpp"
#include "kernels/mesh/generate.hpp"
#include "kernels/mpm/mpm.hpp"
#include "kernels/mpm/simulation.hpp"
#include "tests/kernels/mpm_test_helpers.hpp"

namespace suite::mpm {
namespace {

using testing::mass_in_id_order;
using testing::Team;

// step() phase by phase, with a look at the nodes between P2G and the grid update: returns
// the sum over the nodes of the raw forces (gravity plus internal forces), and writes the
// walls' reaction: the force that stops, within the step, the normal momentum each wall node
// would otherwise have, -(p + dt f)_normal / dt. Must stay step()'s sequence;
// MpmMomentum.MeasuredStepIsStep holds it to that.
std::array<double, 3> step_measuring_walls(State& st, std::array<double, 3>& reaction) {
    p2g(st);
    std::array<double, 3> total{0, 0, 0};
    reaction = {0, 0, 0};
    for (std::size_t n = 0; n < st.node_hi; ++n) {
        const NodeState& s = st.nodes[n];
        if (!(s.m > 0)) continue;
        for (int k = 0; k < 3; ++k) {
            total[k] += s.f[k];
            if (st.grid.wall[n] & (1u << k)) reaction[k] -= s.p[k] / st.dt + s.f[k];
        }
    }
    update_grid(st);
    g2p(st);
    update_stress(st);
    locate(st);
    st.time += st.dt;
    ++st.steps;
    return total;
}

TEST(MpmFreeFall, PositionsFollowSymplecticEulerAndMassIsKept) {
    // Away from every wall, nothing but gravity acts (the velocity field is uniform, so the
    // stress stays 0 to rounding). The step takes v_n = v_{n-1} + dt g (G2P's velocity update)
    // and then x_n = x_{n-1} + dt v_n (the grid momentum already holds dt f), hence
    // z_n = z_0 + g dt² n(n+1)/2: symplectic Euler, not z_0 + g dt² n(n-1)/2 (explicit Euler).
    Team team(1);
    Settings s;
    s.region = {{0.3, 0.35, 0.55}, {0.7, 0.65, 0.9}};
    State st = make_state(make_grid(mesh::box_mesh(8, 8, 8)), s, Strategy::serial, 1);
    const Particles start = st.particles;
    const double m0 = mass_in_id_order(st.particles), g = s.gravity[2], dt = st.dt;
    const int steps = 25;
    for (int n = 1; n <= steps; ++n) {
        step(st);
        EXPECT_EQ(mass_in_id_order(st.particles), m0) << "step " << n;
    }
    double lowest = 1;
    const Particles& p = st.particles;
    for (std::size_t i = 0; i < p.size(); ++i) {
        ASSERT_EQ(p.id[i], start.id[i]);  // no reordering here: same index, same particle
        const double z = start.z[i] + g * dt * dt * steps * (steps + 1) / 2;
        EXPECT_NEAR(p.z[i], z, 1e-13) << "particle " << p.id[i];
        EXPECT_NEAR(p.x[i], start.x[i], 1e-13);
        EXPECT_NEAR(p.y[i], start.y[i], 1e-13);
        EXPECT_NEAR(p.vz[i], g * st.time, 1e-12 * std::fabs(g * st.time));
        EXPECT_NEAR(p.vx[i], 0, 1e-12);
        EXPECT_NEAR(p.vy[i], 0, 1e-12);
        lowest = std::min(lowest, p.z[i]);
    }
    EXPECT_GT(lowest, 0.125) << "the fall reached the floor's elements; the test is no longer free fall";
    EXPECT_EQ(st.clamped, 0u);
}

TEST(MpmMomentum, MeasuredStepIsStep) {
    Team team(1);
    Settings s;
    s.region = {{0.3, 0.3, 0}, {0.7, 0.7, 0.3}};
    State a = make_state(make_grid(mesh::box_mesh(6, 6, 6)), s, Strategy::serial, 1);
    for (int n = 0; n < 5; ++n) step(a);
    State b = a;
    step(a);
    std::array<double, 3> r;
    step_measuring_walls(b, r);
    EXPECT_EQ(a.particles.x, b.particles.x);
    EXPECT_EQ(a.particles.vz, b.particles.vz);
    EXPECT_EQ(a.particles.stress[2], b.particles.stress[2]);
    EXPECT_EQ(a.particles.volume, b.particles.volume);
    EXPECT_EQ(a.time, b.time);
}

TEST(MpmMomentum, ChangesOnlyByGravityAndTheFloorsReaction) {
    // A block resting on the floor, away from the side walls. Per step, G2P changes the
    // particles' momentum by the grid's change of momentum (each node's shared out in
    // proportion to the mass it got): dt Σ_n f_n, where Σ_n f_n = M g since the internal forces
    // cancel (Σ_i ∇N_i = 0 in every element), plus what the floor takes away from its nodes,
    // dt R. So x and y change by rounding only, z by dt (M g + R).
    // The floor is a two-sided constraint (it zeroes the normal velocity either way), so R is
    // not forced >= 0 at every step; but the block stays on the floor and its momentum is
    // bounded, so over a long window R averages to -M g (upward): what a floor must do.
    Team team(1);
    Settings s;
    s.region = {{0.3, 0.3, 0}, {0.7, 0.7, 0.3}};
    State st = make_state(make_grid(mesh::box_mesh(10, 10, 10)), s, Strategy::serial, 1);
    const double mass = mass_in_id_order(st.particles), dt = st.dt, g = s.gravity[2];
    const double scale = dt * mass * std::fabs(g);  // the momentum gravity gives in a step
    const int steps = 400, settled = 100;           // the block's period 4 H / c is ~25 steps
    double reaction_sum = 0, lowest_reaction = 1e300;
    for (int n = 0; n < steps; ++n) {
        const Totals before = totals(st.particles);
        std::array<double, 3> r;
        const std::array<double, 3> force = step_measuring_walls(st, r);
        const Totals after = totals(st.particles);
        ASSERT_EQ(r[0], 0) << "step " << n << ": a node on an x wall has mass";
        ASSERT_EQ(r[1], 0) << "step " << n << ": a node on a y wall has mass";
        EXPECT_NEAR(force[0], 0, 1e-12 * mass * std::fabs(g)) << "step " << n;
        EXPECT_NEAR(force[1], 0, 1e-12 * mass * std::fabs(g)) << "step " << n;
        EXPECT_NEAR(force[2], mass * g, 1e-12 * mass * std::fabs(g)) << "step " << n;
        EXPECT_NEAR(after.momentum[0] - before.momentum[0], 0, 1e-12 * scale) << "step " << n;
        EXPECT_NEAR(after.momentum[1] - before.momentum[1], 0, 1e-12 * scale) << "step " << n;
        EXPECT_NEAR(after.momentum[2] - before.momentum[2], dt * (mass * g + r[2]), 1e-12 * scale) << "step " << n;
        if (n >= settled) {
            reaction_sum += r[2];
            lowest_reaction = std::min(lowest_reaction, r[2]);
        }
    }
    const double mean = reaction_sum / (steps - settled);
    EXPECT_GT(mean, 0);
    // Measured: 0.991 M|g|, never below 0.47 M|g| after step 100.
    EXPECT_NEAR(mean, -mass * g, 0.05 * mass * std::fabs(g)) << "lowest reaction " << lowest_reaction;
    EXPECT_EQ(st.clamped, 0u);
}

TEST(MpmStress, ALinearVelocityFieldGivesTheJaumannIncrement) {
    // Every particle of a block (no gravity) given v = L x and the same stress σ0. Deep inside
    // the block the step is exact: the internal forces cancel at a node whose elements all hold
    // particles (σ uniform, Σ_e |e| ∇N_i = 0), so the particles of elements with only such
    // nodes keep v = L x through G2P; a node whose elements are all of those gets the velocity
    // L x̄_n, x̄_n its particles' mass centre, which is X_n (the star of a Kuhn vertex and the
    // 4-point rule are centrally symmetric); and in an element with only such nodes ∇v = L.
    // In a block of 6 cubes a side that leaves the inner 2 x 2 x 2 cubes.
    // There the stress must become σ0 + λ tr(D) I + 2μ D + W σ0 - σ0 W and V grow by
    // 1 + tr(D), with D and W the symmetric and skew parts of L dt. The spin term is the
    // only check of the Jaumann rate's sign: the dam's rotations are too small to show it.
    Team team(1);
    Settings s;
    s.gravity[2] = 0;
    s.region = {{0.125, 0.125, 0.125}, {0.875, 0.875, 0.875}};
    State st = make_state(make_grid(mesh::box_mesh(8, 8, 8)), s, Strategy::serial, 1);
    const double l[3][3] = {{0.2, -1.0, 0.1}, {1.0, -0.1, 0.0}, {0.3, 0.4, 0.05}};
    const double s0[3][3] = {{1000, 300, 0}, {300, -500, 200}, {0, 200, 100}};
    Particles& p = st.particles;
    for (std::size_t i = 0; i < p.size(); ++i) {
        const double x[3] = {p.x[i], p.y[i], p.z[i]};
        double* v[3] = {&p.vx[i], &p.vy[i], &p.vz[i]};
        for (int a = 0; a < 3; ++a) *v[a] = l[a][0] * x[0] + l[a][1] * x[1] + l[a][2] * x[2];
        const int k[6][2] = {{0, 0}, {1, 1}, {2, 2}, {0, 1}, {1, 2}, {2, 0}};
        for (int c = 0; c < 6; ++c) p.stress[c][i] = s0[k[c][0]][k[c][1]];
    }
    const Particles before = p;
    step(st);
    const Material& mat = s.material;
    const double lambda = mat.young * mat.poisson / ((1 + mat.poisson) * (1 - 2 * mat.poisson));
    const double mu = mat.young / (2 * (1 + mat.poisson)), dt = st.dt;
    double d[3][3], w[3][3], expect[3][3];
    for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) d[a][b] = 0.5 * dt * (l[a][b] + l[b][a]), w[a][b] = 0.5 * dt * (l[a][b] - l[b][a]);
    const double tr = d[0][0] + d[1][1] + d[2][2];
    for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) {
            expect[a][b] = s0[a][b] + 2 * mu * d[a][b] + (a == b ? lambda * tr : 0);
            for (int k = 0; k < 3; ++k) expect[a][b] += w[a][k] * s0[k][b] - s0[a][k] * w[k][b];
        }
    const double tol = 1e-12 * (1000 + mat.young * dt);
    int inner = 0;
    for (std::size_t i = 0; i < p.size(); ++i) {
        const double x[3] = {before.x[i], before.y[i], before.z[i]};
        bool deep = true;
        for (double c : x) deep = deep && c > 0.375 && c < 0.625;
        if (!deep) continue;
        ++inner;
        EXPECT_NEAR(p.stress[0][i], expect[0][0], tol);
        EXPECT_NEAR(p.stress[1][i], expect[1][1], tol);
        EXPECT_NEAR(p.stress[2][i], expect[2][2], tol);
        EXPECT_NEAR(p.stress[3][i], expect[0][1], tol);
        EXPECT_NEAR(p.stress[4][i], expect[1][2], tol);
        EXPECT_NEAR(p.stress[5][i], expect[2][0], tol);
        EXPECT_NEAR(p.volume[i], before.volume[i] * (1 + tr), 1e-12 * before.volume[i]);
    }
    EXPECT_EQ(inner, 2 * 2 * 2 * 6 * 4);
}

// The mass centre's height.
double mass_centre_z(const Particles& p) {
    double mz = 0, m = 0;
    for (std::size_t i = 0; i < p.size(); ++i) mz += p.mass[i] * p.z[i], m += p.mass[i];
    return mz / m;
}

// mpm::energy's total: kinetic + potential (above z = 0) + elastic.
double total_energy(const State& st) { return mpm::energy(st).total(); }

TEST(MpmConfinedColumn, SettlesLikeTheOneDimensionalBar) {
    // A layer filling the box's whole width (every side wall holds it, so it strains in z
    // only) under gravity switched on at t = 0. The exact solution: the static sag
    // u(z) = ρ g (H z - z²/2) / M with the constrained modulus M = λ + 2μ, so the mass centre
    // sinks by ρ g H² / (3 M) at rest; started unstrained, every mode has a period of
    // 4 H / c / (2k - 1), so at T/2 = 2 H / c the sag is exactly twice the static one, and at
    // T it is back to 0. The stress law, the force and the walls all enter the numbers.
    Team team(1);
    Settings s;
    s.region = {{0, 0, 0}, {1, 1, 0.5}};
    State st = make_state(make_grid(mesh::box_mesh(8, 8, 8)), s, Strategy::serial, 1);
    const Material& mat = s.material;
    const double z0 = mass_centre_z(st.particles), H = 2 * z0;
    const double modulus = mat.young * (1 - mat.poisson) / ((1 + mat.poisson) * (1 - 2 * mat.poisson));
    const double sag = mat.density * std::fabs(s.gravity[2]) * H * H / (3 * modulus);
    const double period = 4 * H / mat.wave_speed() / st.dt;  // in steps (28.3 here)
    double deepest = 0, shallowest_after = 1;
    int deepest_at = 0;
    for (int n = 1; n <= static_cast<int>(period * 1.1); ++n) {
        step(st);
        const double d = z0 - mass_centre_z(st.particles);
        if (d > deepest) deepest = d, deepest_at = n;
        if (n > 0.75 * period) shallowest_after = std::min(shallowest_after, d);
    }
    EXPECT_NEAR(deepest, 2 * sag, 0.05 * 2 * sag);  // measured 0.7 % under, at step 14
    EXPECT_NEAR(deepest_at, period / 2, 0.1 * period);
    EXPECT_LT(shallowest_after, 0.1 * sag);  // measured 0.04 of it
    EXPECT_GT(shallowest_after, -0.1 * sag);
    EXPECT_EQ(st.clamped, 0u);
}

TEST(MpmDamCollapse, ThousandStepsSettleAboutTheStaticShape) {
    // Setup's defaults: the column 0.4 x 0.4 x 0.8 in the corner, E = 1e5, ν = 0.3, ρ = 1000,
    // on box:12,12,12 (5800 particles, 0.4 s in Release on one thread). The material is
    // elastic and nothing damps it, so the column does not come to rest: it sags and bulges
    // within the first ~40 steps and then oscillates about that shape with the bar's period
    // 4 L / sqrt(E / ρ) (0.32 s, ~80 steps), the front (largest x) swinging by about ±0.01.
    // Measured: the front's mean over steps 301-500 is 0.4154 and over 701-1000 0.4167, while
    // the swing grows a little: from step ~500 the scheme gains energy (553 J to 569 J by step
    // 1000, of which ~50 J is the oscillation's; at Courant 0.4 it does not, docs/mpm.md). So
    // "levels off" is asserted of window means: over steps 301-500 the front is out by about
    // the static bulge, and over the last 300 steps its mean has moved by much less than that.
    //   The static estimate for a column of height L on a frictionless floor (the walls at
    // x = 0 and y = 0 are planes of symmetry): uniaxial stress σ_zz = -ρ g (L - z), so the
    // mass centre sinks by ρ g L² / (3 E) and the foot bulges out by ν ρ g L x_front / E.
    Team team(1);
    mpm::Setup setup;  // (qualified: gtest's Test has a Setup member)
    setup.mesh = "box:12,12,12";
    setup.particles = "sorted";
    State st = build(setup);
    const Material& mat = setup.settings.material;
    const double g = std::fabs(setup.settings.gravity[2]);
    const double mass = mass_in_id_order(st.particles), e0 = total_energy(st);
    const double f0 = front(st.particles), z0 = mass_centre_z(st.particles), L = 2 * z0;
    const double sag = mat.density * g * L * L / (3 * mat.young),
                 bulge = mat.poisson * mat.density * g * L * f0 / mat.young;
    double early = 0, late = 0, sunk = 0, highest = 0, lowest_z = 1;
    for (int n = 1; n <= 1000; ++n) {
        advance(st, setup);
        const Particles& p = st.particles;
        for (std::size_t i = 0; i < p.size(); ++i) {
            ASSERT_TRUE(std::isfinite(p.x[i] + p.y[i] + p.z[i] + p.vx[i] + p.vy[i] + p.vz[i]))
                << "step " << n << " particle " << p.id[i];
            ASSERT_TRUE(p.x[i] >= 0 && p.x[i] <= 1 && p.y[i] >= 0 && p.y[i] <= 1 && p.z[i] >= 0 && p.z[i] <= 1)
                << "step " << n;
            lowest_z = std::min(lowest_z, p.z[i]);
        }
        const double f = front(p);
        highest = std::max(highest, f);
        if (n > 300 && n <= 500) early += f / 200;
        if (n > 700) late += f / 300;
        if (n > 500) sunk += (z0 - mass_centre_z(p)) / 500;
    }
    EXPECT_EQ(mass_in_id_order(st.particles), mass);
    // The walls held every particle: none had to be put back into the box (g2p's clamp), and
    // the lowest stayed above the floor (seeded at 0.012, down to 0.007 in the run).
    EXPECT_EQ(st.clamped, 0u);
    EXPECT_GT(lowest_z, 0.002);
    // Measured: sag 1.12 of the estimate; advance 1.06 (steps 301-500); late drift 0.13 of the
    // advance; highest front f0 + 2.3 bulges; energy +2.9 %.
    EXPECT_GT(sunk, 0.8 * sag);
    EXPECT_LT(sunk, 1.4 * sag);
    EXPECT_GT(early - f0, 0.5 * bulge);
    EXPECT_LT(early - f0, 2.0 * bulge);
    EXPECT_LT(std::fabs(late - early), 0.5 * (early - f0));
    EXPECT_LT(highest, f0 + 4 * bulge);
    EXPECT_NEAR(total_energy(st), e0, 0.05 * e0);
}

TEST(MpmBadInput, MakeStateRefusesWhatCannotRun) {
    const Grid grid = make_grid(mesh::box_mesh(4, 4, 4));
    auto refused = [&](const Settings& s, const std::string& says, bool force = false) {
        try {
            make_state(grid, s, Strategy::serial, 1, force);
        } catch (const UsageError& e) {
            EXPECT_NE(std::string(e.what()).find(says), std::string::npos) << e.what();
            return true;
        }
        return false;
    };
    Settings s;
    EXPECT_FALSE(refused(s, ""));
    Settings ppe = s;
    ppe.per_element = 0;
    EXPECT_TRUE(refused(ppe, "--ppe=0"));
    for (double nu : {0.5, 0.6, -1.0}) {
        Settings bad = s;
        bad.material.poisson = nu;
        EXPECT_TRUE(refused(bad, "--poisson")) << nu;
    }
    for (double e : {0.0, -1e5}) {
        Settings bad = s;
        bad.material.young = e;
        EXPECT_TRUE(refused(bad, "--young")) << e;
    }
    Settings rho = s;
    rho.material.density = 0;
    EXPECT_TRUE(refused(rho, "--density"));
    for (const Region& r : {Region{{0, 0, 0}, {0.4, 0.4, 1.2}}, Region{{-0.1, 0, 0}, {0.4, 0.4, 0.8}},
                            Region{{1.5, 1.5, 1.5}, {2, 2, 2}}}) {
        Settings bad = s;
        bad.region = r;
        EXPECT_TRUE(refused(bad, "region"));
    }
    Settings fast = s;
    fast.dt = 1.5 * critical_step(grid, s.material);
    EXPECT_TRUE(refused(fast, "--dt"));
    EXPECT_FALSE(refused(fast, "", true));  // --force runs it
    fast.dt = 0.99 * critical_step(grid, s.material);
    EXPECT_FALSE(refused(fast, ""));
}

TEST(MpmBadInput, TheGridMustBeTetrahedral) {
    EXPECT_THROW(make_grid(mesh::disk_mesh(2)), UsageError);
    mpm::Setup setup;
    setup.mesh = "disk:refine=2";
    EXPECT_THROW(build(setup), UsageError);
    setup.mesh = "box:4,4,4";
    setup.settings.per_element = 0;
    EXPECT_THROW(build(setup), UsageError);
    setup.settings.per_element = 4;
    setup.settings.dt = 1;
    EXPECT_THROW(build(setup), UsageError);
    setup.force = true;
    EXPECT_NO_THROW(build(setup));
}

}  // namespace
}  // namespace suite::mpm

namespace suite::mpm {
namespace {

// The column case (case_settings("column")) settled by damping on box:N, run to 4.9 s.
Outcome settled_column(int n, Integration integration) {
    Team team(1);
    mpm::Setup s;
    s.mesh = "box:" + std::to_string(n) + "," + std::to_string(n) + "," + std::to_string(n);
    s.settings = case_settings("column");
    s.settings.integration = integration;
    s.settings.damping = 10;
    State st = build(s);
    SimulationSettings run;
    run.column = true;
    run.steps = static_cast<std::uint64_t>(100 * n);
    run.vtk_every = 0;
    return simulate(st, s, run, {});
}

TEST(MpmColumn, MixedIntegrationConvergesToTheOneDimensionalSettlement) {
    // The layer 1 x 1 x 0.5 between slip walls settles by ρ g H² / (2 M) = 9.11 mm at its top.
    // With every element integrated over its particles, the top sank 5.9 % too far on box:16
    // (and 13 % undamped, 20 % on box:32): particles crossing faces change the volume an element
    // sees. Mixed integration (docs/mpm.md, "The column"), measured: box:8 -3.2 %, box:16 -2.1 %,
    // box:32 -1.2 % (σzz RMS 7.1 %, 3.6 %, 1.7 % of ρ g H).
    const Outcome coarse = settled_column(8, Integration::mixed), fine = settled_column(16, Integration::mixed);
    ASSERT_TRUE(coarse.passed()) << coarse.failure;
    ASSERT_TRUE(fine.passed()) << fine.failure;
    EXPECT_NEAR(coarse.settlement_exact, 9.1e-3, 0.02e-3);
    EXPECT_LT(std::fabs(coarse.settlement_error), 0.04);
    EXPECT_LT(std::fabs(fine.settlement_error), 0.8 * std::fabs(coarse.settlement_error));
    EXPECT_LT(fine.stress_rms, 0.6 * coarse.stress_rms);
    EXPECT_LT(fine.stress_rms, 0.05);
}

TEST(MpmColumn, ParticleIntegrationFailsTheColumnCheckOnTheFinerGrid) {
    // The check can fail: the grid-crossing error, which grows under refinement.
    const Outcome r = settled_column(16, Integration::particle);
    ASSERT_FALSE(r.passed());
    EXPECT_NE(r.failure.find("column: settled (damped"), std::string::npos) << r.failure;
    EXPECT_GT(r.settlement_error, 0.05);
}

}  // namespace
}  // namespace suite::mpm
