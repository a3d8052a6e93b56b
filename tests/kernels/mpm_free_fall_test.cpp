// The free-fall case (kernels/mpm/choices.cpp, free_fall.hpp): until a wall acts, every particle
// is where the explicit step puts a body falling from rest, to rounding; that fall is g t dt / 2
// from the analytic z0 - g t² / 2, an error that halves with the grid's spacing (the Courant step
// halves with it); and the check fails for a state that does not fall as one body.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <string>

#include "kernels/mpm/choices.hpp"
#include "kernels/mpm/mpm.hpp"
#include "kernels/mpm/simulation.hpp"
#include "tests/kernels/mpm_test_helpers.hpp"

namespace suite::mpm {
namespace {

using testing::Team;

struct Fall {
    Outcome outcome;
    double dt = 0, time = 0;
};

// The free-fall case on box:N for `seconds` of simulated time; `nudge` > 0 starts one particle
// moving sideways at that speed (m/s).
Fall fall(int n, double seconds, double nudge = 0) {
    Team team(1);
    Setup s;
    s.mesh = "box:" + std::to_string(n) + "," + std::to_string(n) + "," + std::to_string(n);
    s.settings = cases().at("free-fall").what.settings;
    State st = build(s);
    if (nudge > 0) st.particles.vx[0] = nudge;
    SimulationSettings run;
    run.free_fall = true;
    run.steps = static_cast<std::uint64_t>(std::floor(seconds / st.dt));
    run.vtk_every = 0;
    Fall f;
    f.dt = st.dt;
    f.outcome = simulate(st, s, run, {});
    f.time = st.time;
    return f;
}

TEST(MpmFreeFall, EveryParticleFallsExactlyAsTheStepSaysAndTheErrorHalvesWithTheGrid) {
    // 0.2 s: the block falls 0.2 m of the 0.5 m below it, no wall near.
    const Fall coarse = fall(8, 0.2), fine = fall(16, 0.2);
    for (const Fall* f : {&coarse, &fine}) {
        ASSERT_TRUE(f->outcome.passed()) << f->outcome.failure;
        const Outcome& r = f->outcome;
        EXPECT_EQ(r.fall_steps, r.steps_done) << "a wall acted before 0.2 s";
        EXPECT_LE(r.fall_worst, 1e-12);
        // The mean fall is g t dt / 2 short of g t² / 2, as the step's algebra says.
        const double bound = 0.5 * 9.81 * f->time * f->dt;
        EXPECT_NEAR(r.fall_bound, bound, 1e-12 * bound + 1e-15);
        EXPECT_NEAR(r.fall_analytic, bound, 1e-9);
    }
    EXPECT_NEAR(fine.dt / coarse.dt, 0.5, 0.05);
    EXPECT_LT(fine.outcome.fall_analytic, 0.55 * coarse.outcome.fall_analytic);
}

TEST(MpmFreeFall, TheCheckFailsForAStateThatDoesNotFallAsOneBody) {
    const Fall f = fall(8, 0.05, 1e-3);
    ASSERT_FALSE(f.outcome.passed());
    EXPECT_EQ(f.outcome.failure.rfind("free fall: ", 0), 0u) << f.outcome.failure;
    // Far beyond the check's 1e-9 m: the nudged particle's momentum reaches its neighbours' nodes.
    EXPECT_GT(f.outcome.fall_worst, 1e-8);
}

TEST(MpmFreeFall, TheCaseIsOneEntryOfTheTable) {
    const Case& c = cases().at("free-fall").what;
    EXPECT_FALSE(c.fluid());
    EXPECT_EQ(c.reference, Reference::free_fall);
    EXPECT_EQ(c.column, ColumnOption::none);
    // Not in version 1's frozen order: no old file can name it by an index.
    for (const auto& old : case_order_v1()) EXPECT_NE(old, "free-fall");
}

}  // namespace
}  // namespace suite::mpm
