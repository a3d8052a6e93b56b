// Implicit MPM (kernels/mpm/implicit.hpp): the tangent against a finite difference of the
// internal force, Newton's quadratic convergence, the static column against the one-dimensional
// answer, the implicit run against the explicit one at the explicit step and its energy at 10x
// and 50x that step, the same answer in every order and strategy and from CHOLMOD, bad input.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "harness/common/units.hpp"
#include "kernels/fem/sparse_libs.hpp"
#include "kernels/mpm/implicit.hpp"
#include "kernels/mpm/simulation.hpp"
#include "tests/kernels/mpm_test_helpers.hpp"

namespace suite::mpm {
namespace {

using testing::Team;

mpm::Setup implicit_setup(const std::string& mesh, Integrator integrator, double dt_multiple) {
    mpm::Setup s;
    s.mesh = mesh;
    s.settings = case_settings("dam-collapse");
    s.settings.integrator = integrator;
    const State probe = build(s);
    s.settings.dt = dt_multiple * critical_step(probe.grid, s.settings.material);
    return s;
}

// f_int at the system's current Δu.
std::vector<double> internal_force(State& st) {
    implicit_assemble(st, false);
    return st.system.fint;
}

// The tangent times d, from the assembled (unfinished) tangent.
std::vector<double> tangent_times(const State& st, const std::vector<double>& d) {
    const ActiveSystem& s = st.system;
    std::vector<double> y(s.rows(), 0);
    for (std::size_t i = 0; i < s.rows(); ++i)
        for (std::uint32_t k = s.row_ptr[i]; k < s.row_ptr[i + 1]; ++k) y[i] += s.val[k] * d[s.col[k]];
    return y;
}

double relative_tangent_error(bool large) {
    Team team(1);
    mpm::Setup s = implicit_setup("box:4,4,4", Integrator::implicit, 5);
    s.settings.implicit.large_strain = large;
    State st = build(s);
    for (int k = 0; k < 3; ++k) step(st);  // stress and motion
    EXPECT_TRUE(st.implicit.failure.empty()) << st.implicit.failure;
    implicit_project(st);
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> u(-1, 1);
    ActiveSystem& sys = st.system;
    for (double& x : sys.du) x += 0.02 * u(rng);  // a few percent of an element's 0.25: large strains
    std::vector<double> d(sys.rows());
    for (double& x : d) x = u(rng);
    implicit_assemble(st, true);
    const std::vector<double> kd = tangent_times(st, d);
    const std::vector<double> base = sys.du;
    const double h = 1e-6;
    for (std::size_t i = 0; i < d.size(); ++i) sys.du[i] = base[i] + h * d[i];
    const std::vector<double> plus = internal_force(st);
    for (std::size_t i = 0; i < d.size(); ++i) sys.du[i] = base[i] - h * d[i];
    const std::vector<double> minus = internal_force(st);
    double num = 0, den = 0;
    for (std::size_t i = 0; i < d.size(); ++i) {
        const double fd = (plus[i] - minus[i]) / (2 * h);
        num += (fd - kd[i]) * (fd - kd[i]);
        den += kd[i] * kd[i];
    }
    return std::sqrt(num / den);
}

// The finished tangent (the mass term, the walls' identity rows) against a central difference of
// the residual r = m g - f_int - m a'(Δu) on the free rows: K d = -dr/dΔu d.
double relative_newton_matrix_error() {
    Team team(1);
    State st = build(implicit_setup("box:4,4,4", Integrator::implicit, 5));
    for (int k = 0; k < 3; ++k) step(st);
    implicit_project(st);
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> u(-1, 1);
    ActiveSystem& sys = st.system;
    for (std::size_t i = 0; i < sys.rows(); ++i) sys.du[i] += sys.fixed[i] ? 0 : 0.02 * u(rng);
    std::vector<double> d(sys.rows());
    for (std::size_t i = 0; i < d.size(); ++i) d[i] = sys.fixed[i] ? 0 : u(rng);
    implicit_assemble(st, true);
    implicit_finish_tangent(st);
    const std::vector<double> kd = tangent_times(st, d);
    const std::vector<double> base = sys.du;
    const double h = 1e-6;
    std::vector<double> rp, rm;
    for (double sign : {1.0, -1.0}) {
        for (std::size_t i = 0; i < d.size(); ++i) sys.du[i] = base[i] + sign * h * d[i];
        implicit_assemble(st, false);
        implicit_residual(st);
        (sign > 0 ? rp : rm) = sys.r;
    }
    double num = 0, den = 0;
    std::size_t fixed = 0;
    for (std::size_t i = 0; i < d.size(); ++i) {
        if (sys.fixed[i]) {
            ++fixed;
            EXPECT_EQ(kd[i], 0) << "a fixed row of K d";  // d is 0 there, and the row is the identity's
            continue;
        }
        const double fd = -(rp[i] - rm[i]) / (2 * h);
        num += (fd - kd[i]) * (fd - kd[i]);
        den += kd[i] * kd[i];
    }
    EXPECT_GT(fixed, 0u) << "the walls hold some rows";
    return std::sqrt(num / den);
}

TEST(MpmImplicit, TheNewtonMatrixIsTheDerivativeOfTheResidual) {
    const double e = relative_newton_matrix_error();
    std::printf("K d against a central difference of the residual: %.3g relative\n", e);
    EXPECT_LT(e, 1e-6);
}

TEST(MpmImplicit, TangentIsTheDerivativeOfTheInternalForce) {
    const double large = relative_tangent_error(true), small = relative_tangent_error(false);
    std::printf("tangent vs central difference, relative: large strain %.3g, small strain %.3g\n", large, small);
    EXPECT_LT(large, 1e-6);
    EXPECT_LT(small, 1e-6);
}

TEST(MpmImplicit, NewtonConvergesQuadratically) {
    Team team(1);
    mpm::Setup s = implicit_setup("box:8,8,8", Integrator::implicit, 50);
    State st = build(s);
    int nonlinear = 0;
    for (int k = 0; k < 4; ++k) {
        step(st);
        ASSERT_TRUE(st.implicit.failure.empty()) << st.implicit.failure;
        const std::vector<double>& r = st.implicit.last_residuals;
        std::printf("step %d: ||r_k|| / ||r_0||:", k + 1);
        for (double x : r) std::printf(" %.3g", x);
        std::printf("\n");
        for (std::size_t i = 1; i + 1 < r.size(); ++i)
            if (r[i] < 1e-2 && r[i + 1] > 1e-13) {
                // Quadratic: the exponent doubles (log r_{k+1} / log r_k near 2).
                EXPECT_GT(std::log(r[i + 1]) / std::log(r[i]), 1.7) << "step " << k + 1 << " iteration " << i;
                ++nonlinear;
            }
    }
    EXPECT_GT(nonlinear, 0) << "no iteration in the quadratic range: the test saw nothing";
}

Outcome static_column(int n, bool large) {
    Team team(1);
    mpm::Setup s;
    s.mesh = "box:" + std::to_string(n) + "," + std::to_string(n) + "," + std::to_string(n);
    s.settings = case_settings("column");
    s.settings.integrator = Integrator::quasi_static;
    s.settings.implicit.large_strain = large;
    State st = build(s);
    SimulationSettings run;
    run.column = true;
    run.steps = 2;
    run.vtk_every = 0;
    return simulate(st, s, run, {});
}

TEST(MpmImplicit, StaticColumnConvergesToTheOneDimensionalSettlement) {
    const Outcome c8 = static_column(8, false), c16 = static_column(16, false);
    const Outcome l16 = static_column(16, true);
    std::printf(
        "static column, small strain: box:8 %.3f %%, box:16 %.3f %% (stress RMS %.3f %%, %.3f %%; layer means %.3f %%, "
        "%.3f %%); "
        "large strain box:16 %.3f %%\n",
        100 * c8.settlement_error, 100 * c16.settlement_error, 100 * c8.stress_rms, 100 * c16.stress_rms,
        100 * c8.stress_profile, 100 * c16.stress_profile, 100 * l16.settlement_error);
    ASSERT_TRUE(c8.passed()) << c8.failure;
    ASSERT_TRUE(c16.passed()) << c16.failure;
    EXPECT_LT(std::fabs(c16.settlement_error), 0.02);
    EXPECT_LT(std::fabs(c16.settlement_error), std::fabs(c8.settlement_error));
    // The stress profile: each layer's mean against the exact, within 2 % of ρ g H and falling
    // (measured 1.3 % and 1.0 %).
    EXPECT_LT(c16.stress_profile, 0.02);
    EXPECT_LT(c16.stress_profile, c8.stress_profile);
}

double mean_z(const State& st) {
    double z = 0;
    for (double v : st.particles.z) z += v;
    return z / static_cast<double>(st.particles.size());
}

TEST(MpmImplicit, AgreesWithTheExplicitRunAtTheExplicitStep) {
    // The dam collapse at 0.8 of the stable step through its first fall (0.15 s, to the lowest
    // point of its bounce): the material's mean height, explicit (USL, Jaumann rate) against
    // implicit (Newmark, the step's Green-Lagrange strain) and against implicit at a quarter of
    // that step. The two integrators differ at first order in dt and in the stress law at finite
    // strain, and the bounce is an oscillation whose phase accumulates those differences, so the
    // tolerance is a share of the settlement over the first fall, where the phase has not yet
    // drifted: 8 % (measured 5.9 %), a gap that narrows when both take a quarter of the step
    // (4.6 %: the rest is the stress laws); the implicit run against itself at dt / 4: 3 %
    // (measured 2.2 %).
    Team team(1);
    State ex = build(implicit_setup("box:8,8,8", Integrator::explicit_step, 0.8));
    State im = build(implicit_setup("box:8,8,8", Integrator::implicit, 0.8));
    State fine = build(implicit_setup("box:8,8,8", Integrator::implicit, 0.2));
    State ex_fine = build(implicit_setup("box:8,8,8", Integrator::explicit_step, 0.2));
    const double z0 = mean_z(ex);
    double deepest = 0, apart = 0, refined = 0, apart_fine = 0;
    for (int k = 0; k < 24; ++k) {
        step(ex);
        step(im);
        for (int j = 0; j < 4; ++j) {
            step(fine);
            step(ex_fine);
        }
        ASSERT_TRUE(im.implicit.failure.empty() && fine.implicit.failure.empty())
            << im.implicit.failure << fine.implicit.failure;
        deepest = std::max(deepest, z0 - mean_z(ex));
        apart = std::max(apart, std::fabs(mean_z(ex) - mean_z(im)));
        refined = std::max(refined, std::fabs(mean_z(fine) - mean_z(im)));
        apart_fine = std::max(apart_fine, std::fabs(mean_z(fine) - mean_z(ex_fine)));
    }
    std::printf(
        "first fall (%.3f s): mean height fell %.4g m; explicit and implicit apart by at most %.3g m (%.2f %%), "
        "implicit at dt/4 by %.3g m (%.2f %%); both at dt/4 apart by %.3g m (%.2f %%)\n",
        ex.time, deepest, apart, 100 * apart / deepest, refined, 100 * refined / deepest, apart_fine,
        100 * apart_fine / deepest);
    EXPECT_GT(deepest, 0.03);
    EXPECT_LT(apart, 0.08 * deepest);
    EXPECT_LT(apart_fine, apart);
    EXPECT_LT(refined, 0.03 * deepest);
}

// The dam collapse at `multiple` times the explicit stable step for about 1.5 s: the total energy's
// largest rise above its start, as a share of what gravity can release over the run.
double energy_rise(double multiple, const std::string& solver = "cg") {
    Team team(2);
    mpm::Setup s = implicit_setup("box:8,8,8", Integrator::implicit, multiple);
    s.settings.implicit.solver = parse_linear_solver(solver);
    s.strategy = Strategy::partition;
    s.threads = 2;
    State st = build(s);
    const Energy e0 = energy(st);
    double rise = 0, lowest = e0.potential;
    const int steps = static_cast<int>(std::lround(1.5 / st.dt));
    for (int k = 0; k < steps; ++k) {
        step(st);
        EXPECT_TRUE(st.implicit.failure.empty()) << st.implicit.failure;
        if (!st.implicit.failure.empty()) return INFINITY;
        const Energy e = energy(st);
        rise = std::max(rise, e.total() - e0.total());
        lowest = std::min(lowest, e.potential);
    }
    std::printf(
        "%gx the stable step (%d steps of %.3g s): total energy at most %.3g J above its start; the potential fell by "
        "%.3g J\n",
        multiple, steps, st.dt, rise, e0.potential - lowest);
    return rise / (e0.potential - lowest);
}

TEST(MpmImplicit, StaysStableAtTenAndFiftyTimesTheExplicitStep) {
    EXPECT_LT(energy_rise(10), 0.01);
    EXPECT_LT(energy_rise(50), 0.01);
}

// The first `steps` implicit steps of the dam collapse under one order and strategy.
State run_order(const std::string& ordering, const std::string& particles, Strategy strategy, int threads,
                const std::string& solver = "cg") {
    Team team(threads);
    mpm::Setup s = implicit_setup("box:6,6,6", Integrator::implicit, 10);
    s.ordering = ordering;
    s.particles = particles;
    s.sort_every = 2;
    s.strategy = strategy;
    s.threads = threads;
    s.settings.implicit.solver = parse_linear_solver(solver);
    State st = build(s);
    for (int k = 0; k < 5; ++k) {
        advance(st, s);
        EXPECT_TRUE(st.implicit.failure.empty()) << st.implicit.failure;
    }
    return st;
}

TEST(MpmImplicit, EveryOrderStrategyAndSolverGivesTheSameMotion) {
    const State ref = run_order("natural", "seeded", Strategy::serial, 1);
    struct Case {
        const char* ordering;
        const char* particles;
        Strategy strategy;
        int threads;
        const char* solver;
    };
    const Case cases[] = {{"hilbert", "sorted", Strategy::serial, 1, "cg"},
                          {"morton", "dynamic", Strategy::colour, 2, "cg"},
                          {"random", "shuffled", Strategy::atomic, 2, "cg"},
                          {"hilbert", "dynamic", Strategy::partition, 2, "cg"},
                          {"natural", "seeded", Strategy::serial, 1, "cholmod"}};
    for (const Case& c : cases) {
        if (std::string(c.solver) == "cholmod" && !fem::sparse_libs_missing().empty())
            continue;  // built without it: CG alone
        const State st = run_order(c.ordering, c.particles, c.strategy, c.threads, c.solver);
        const double d = testing::max_position_difference(ref.particles, st.particles);
        EXPECT_LT(d, 1e-9) << c.ordering << " " << c.particles << " " << strategy_name(c.strategy) << " " << c.solver;
        EXPECT_GT(st.implicit.newton, 0u);
    }
}

TEST(MpmImplicit, ARenumberedGridGetsANewSystemEvenWithTheSameElementNumbers) {
    // renumber_active puts the active elements first, so two renumberings can leave the same
    // element numbers 0..k-1 naming other elements: the pattern must not be kept on the numbers.
    Team team(1);
    mpm::Setup s = implicit_setup("box:6,6,6", Integrator::implicit, 10);
    State st = build(s);
    renumber_active(st);
    step(st);
    const std::vector<std::uint32_t> before = st.system.elements;
    const std::uint64_t built = st.system.patterns;
    renumber_active(st);
    implicit_project(st);
    EXPECT_EQ(st.system.elements, before) << "the case this test is about: the same numbers";
    EXPECT_EQ(st.system.patterns, built + 1);
}

TEST(MpmImplicit, CholmodTakesOverWhenCgRunsOutOfIterations) {
    if (!fem::sparse_libs_missing().empty()) GTEST_SKIP() << "built without " << fem::sparse_libs_missing();
    const State ref = run_order("natural", "seeded", Strategy::serial, 1);
    Team team(1);
    mpm::Setup s = implicit_setup("box:6,6,6", Integrator::implicit, 10);
    s.sort_every = 2;
    s.settings.implicit.cg_max = 3;
    State st = build(s);
    for (int k = 0; k < 5; ++k) {
        advance(st, s);
        ASSERT_TRUE(st.implicit.failure.empty()) << st.implicit.failure;
    }
    EXPECT_EQ(st.implicit.fallbacks, st.implicit.newton);
    EXPECT_LT(testing::max_position_difference(ref.particles, st.particles), 1e-9);
}

TEST(MpmImplicit, RefusesWhatItCannotRun) {
    mpm::Setup s = implicit_setup("box:4,4,4", Integrator::implicit, 10);
    mpm::Setup fluid = s;
    fluid.settings = case_settings("dam-break");
    fluid.settings.integrator = Integrator::implicit;
    EXPECT_THROW(build(fluid), UsageError);
    for (const auto& [beta, gamma] : {std::pair{0.2, 0.5}, std::pair{0.25, 0.4}, std::pair{0.6, 0.5}}) {
        mpm::Setup bad = s;
        bad.settings.implicit.beta = beta;
        bad.settings.implicit.gamma = gamma;
        EXPECT_THROW(build(bad), UsageError) << beta << "," << gamma;
    }
    mpm::Setup damped = s;
    damped.settings.damping = 1;
    EXPECT_THROW(build(damped), UsageError);
    EXPECT_THROW(parse_integrator("newmark"), UsageError);
    EXPECT_THROW(parse_linear_solver("lu"), UsageError);
}

TEST(MpmImplicit, SaysWhenNewtonOrTheSolveFails) {
    Team team(1);
    // Newton limited to one iteration on a nonlinear step: it cannot converge.
    mpm::Setup s = implicit_setup("box:6,6,6", Integrator::implicit, 50);
    s.settings.implicit.newton_max = 1;
    State st = build(s);
    const State before = st;
    step(st);
    EXPECT_NE(st.implicit.failure.find("Newton did not converge in 1 iterations"), std::string::npos)
        << st.implicit.failure;
    EXPECT_EQ(st.steps, 0u);
    EXPECT_EQ(st.time, 0);
    EXPECT_EQ(st.implicit.failed_steps, 1u);
    EXPECT_EQ(st.implicit.newton, 0u) << "a failed step's iterations are not counted";
    const Particles& a = st.particles;
    const Particles& b = before.particles;
    for (std::size_t i = 0; i < a.size(); ++i) {
        ASSERT_TRUE(a.x[i] == b.x[i] && a.y[i] == b.y[i] && a.z[i] == b.z[i] && a.vx[i] == b.vx[i] &&
                    a.vy[i] == b.vy[i] && a.vz[i] == b.vz[i] && a.volume[i] == b.volume[i] && a.elem[i] == b.elem[i] &&
                    a.id[i] == b.id[i])
            << "particle " << i;
        for (int k = 0; k < 6; ++k) ASSERT_EQ(a.stress[k][i], b.stress[k][i]) << "particle " << i;
        for (int k = 0; k < 3; ++k) ASSERT_EQ(a.accel[k][i], b.accel[k][i]) << "particle " << i;
    }
    // advance() reorders nothing after a failed step, even when a reordering is due.
    mpm::Setup sorted = s;
    sorted.particles = "dynamic";
    sorted.sort_every = 1;
    State d = build(sorted);
    const State d0 = d;
    advance(d, sorted);
    EXPECT_FALSE(d.implicit.failure.empty());
    EXPECT_EQ(d.particles.id[0], d0.particles.id[0]);
    EXPECT_EQ(d.grid.mesh.conn, d0.grid.mesh.conn);
    // A static problem with the material away from every wall: nothing holds it.
    mpm::Setup floating;
    floating.mesh = "box:6,6,6";
    floating.settings = case_settings("dam-collapse");
    floating.settings.integrator = Integrator::quasi_static;
    floating.settings.region = Region{{0.3, 0.3, 0.3}, {0.7, 0.7, 0.7}};
    State f = build(floating);
    step(f);
    EXPECT_NE(f.implicit.failure.find("singular: no wall holds the material in x"), std::string::npos)
        << f.implicit.failure;
    // The same through the simulation: a failed Newton check, marked as the solver's.
    SimulationSettings run;
    run.steps = 3;
    run.vtk_every = 0;
    State g = build(s);
    const Outcome r = simulate(g, s, run, {});
    EXPECT_FALSE(r.passed());
    EXPECT_TRUE(r.solver_failed);
    EXPECT_EQ(r.failure.rfind("Newton: step 1", 0), 0u) << r.failure;
}

}  // namespace
}  // namespace suite::mpm
