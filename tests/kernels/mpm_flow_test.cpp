// The dam break (a weakly compressible fluid that flows and mixes) and the particle orders:
// the fluid's stress law, mass, energy and Ritter's front checked by mpm::simulate on a run
// that reaches the far wall, a run made to outrun Ritter's front failing that check, and how
// each particle order starts and how far the flow takes its locality.
#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "harness/common/units.hpp"
#include "kernels/mpm/simulation.hpp"
#include "tests/kernels/mpm_test_helpers.hpp"

using namespace suite;
using namespace suite::mpm;
using suite::mpm::testing::Team;

namespace {

mpm::Setup dam_break(const std::string& particles) {
    mpm::Setup s;
    s.mesh = "box:8,8,8";
    s.settings = case_settings("dam-break");
    s.particles = particles;
    s.sort_every = 5;
    return s;
}

const Check* find_check(const Outcome& r, const std::string& name) {
    for (const auto& c : r.checks)
        if (c.name == name) return &c;
    return nullptr;
}

}  // namespace

TEST(MpmDamBreak, TheFluidsPressureIsWhatItsVolumeSays) {
    // σ = -p I + 2η dev(D): the mean stress is -p = -max(0, K (V0/V - 1)), whatever D was.
    Team team(1);
    const mpm::Setup s = dam_break("seeded");
    State st = build(s);
    for (int n = 0; n < 40; ++n) advance(st, s);
    const Material& m = st.settings.material;
    const Particles& p = st.particles;
    int compressed = 0, stretched = 0;
    for (std::size_t i = 0; i < p.size(); ++i) {
        const double j = p.volume[i] * m.density / p.mass[i];
        const double pressure = std::max(0.0, m.bulk_modulus() * (1 / j - 1));
        const double mean = (p.stress[0][i] + p.stress[1][i] + p.stress[2][i]) / 3;
        ASSERT_NEAR(-mean, pressure, 1e-9 * m.bulk_modulus()) << "particle " << p.id[i] << ", J = " << j;
        (j < 1 ? compressed : stretched) += 1;
    }
    // Both branches were met: the column's foot is compressed by its weight, its top is not.
    EXPECT_GT(compressed, 100);
    EXPECT_GT(stretched, 10);
}

TEST(MpmDamBreak, ReachesTheFarWallBehindRittersFrontConservingMassWithoutMakingEnergy) {
    Team team(1);
    const mpm::Setup s = dam_break("seeded");
    State st = build(s);
    SimulationSettings run;
    run.steps = 500;
    run.vtk_every = 0;
    const Outcome r = simulate(st, s, run, {});
    ASSERT_TRUE(r.passed()) << r.failure;
    for (const char* name : {"total energy", "Ritter front", "mass", "nodal mass"})
        EXPECT_NE(find_check(r, name), nullptr) << name;
    EXPECT_EQ(r.mass_final, r.mass_initial);
    // The water ran 0.3 m to 1 m: a flow, not a sag (the elastic column's front moves 2 cm).
    double reached = 0;
    for (const auto& row : r.rows) reached = std::max(reached, row.front);
    EXPECT_GT(reached, 0.95);
    EXPECT_LT(r.rows.front().front, 0.4);
    // The step followed the flow: shorter once the water moved (c + |v| > c).
    EXPECT_LT(st.dt_min, 0.95 * st.dt_max);
    // The total energy fell (viscosity, the impact on the far wall) and was never above its start
    // by more than the check's margin: measured, it never rose above it at all.
    const auto total = [](const FrontRow& row) { return row.kinetic + row.potential + row.internal; };
    const double e0 = total(r.rows.front());
    EXPECT_LT(total(r.rows.back()), 0.98 * e0);
    for (const auto& row : r.rows) ASSERT_LE(total(row), e0 * (1 + 1e-9)) << "step " << row.step;
    // Something moved: the kinetic energy reached a good share of the potential released.
    double kmax = 0;
    for (const auto& row : r.rows) kmax = std::max(kmax, row.kinetic);
    EXPECT_GT(kmax, 0.1 * e0);
}

TEST(MpmDamBreak, AFrontFasterThanRittersFailsItsCheck) {
    // The same water thrown at 12 m/s towards the far wall: it outruns the shallow-water front
    // (2 sqrt(g H) = 4.9 m/s), which the check must say, with the step.
    Team team(1);
    const mpm::Setup s = dam_break("seeded");
    State st = build(s);
    for (double& v : st.particles.vx) v = 12;
    SimulationSettings run;
    run.steps = 200;
    run.vtk_every = 0;
    const Outcome r = simulate(st, s, run, {});
    ASSERT_FALSE(r.passed());
    EXPECT_NE(r.failure.find("Ritter front: after step"), std::string::npos) << r.failure << "; " << r.checks.size();
    EXPECT_LT(r.steps_done, 200u);
}

TEST(MpmParticleOrders, SeededIsTheElementLoopsOrderAndShuffledIsNone) {
    Team team(1);
    mpm::Setup s = dam_break("seeded");
    s.ordering = "hilbert";
    const State seeded = build(s);
    // Seeded element by element in the grid's order: 4 particles an element, so 3 of every 4
    // neighbours share one; on a Hilbert grid the elements are neighbours along the curve too.
    const Locality a = locality(seeded);
    EXPECT_NEAR(a.same_element, 0.75, 0.001);
    EXPECT_LT(a.mean_gap, 1.0);
    for (std::size_t i = 1; i < seeded.particles.size(); ++i)
        ASSERT_LE(seeded.particles.elem[i - 1], seeded.particles.elem[i]);
    s.particles = "shuffled";
    const Locality b = locality(build(s));
    EXPECT_LT(b.same_element, 0.01);
    EXPECT_GT(b.mean_gap, 100 * a.mean_gap);
    s.particles = "unsorted";
    try {
        build(s);
        ADD_FAILURE() << "the old name was accepted";
    } catch (const UsageError& e) {
        EXPECT_NE(std::string(e.what()).find(
                      "'unsorted' (now called 'shuffled'); accepted: seeded, shuffled, sorted, dynamic"),
                  std::string::npos)
            << e.what();
    }
}

TEST(MpmParticleOrders, TheFlowScattersTheSeededOrderAndSortingRestoresIt) {
    Team team(1);
    const mpm::Setup seeded = dam_break("seeded"), sorted = dam_break("sorted");
    State a = build(seeded), b = build(sorted);
    const Locality start = locality(a);
    for (int n = 0; n < 400; ++n) {
        advance(a, seeded);
        advance(b, sorted);
    }
    const Locality end = locality(a), resorted = locality(b);
    EXPECT_GT(end.mean_gap, 10 * start.mean_gap) << start.mean_gap << " -> " << end.mean_gap;
    EXPECT_LT(end.same_element, 0.5 * start.same_element);
    // 400 is a multiple of sort_every: b was sorted after its last step, by element in the grid's
    // order (natural here, so its distance along the curve stays the natural order's).
    EXPECT_GT(resorted.same_element, 2 * end.same_element) << end.same_element << " -> " << resorted.same_element;
    for (std::size_t i = 1; i < b.particles.size(); ++i) ASSERT_LE(b.particles.elem[i - 1], b.particles.elem[i]);
}

TEST(MpmDamBreak, AStepAboveTheStableOneFailsTheTotalEnergyCheck) {
    // Three times the stable step (forced): the scheme makes energy, and the total-energy check,
    // taken before the kinetic bound, names it.
    Team team(1);
    mpm::Setup s = dam_break("seeded");
    s.settings.courant = 3;
    s.force = true;
    State st = build(s);
    SimulationSettings run;
    run.steps = 300;
    run.vtk_every = 0;
    const Outcome r = simulate(st, s, run, {});
    ASSERT_FALSE(r.passed());
    EXPECT_NE(r.failure.find("total energy: after step"), std::string::npos) << r.failure;
}
