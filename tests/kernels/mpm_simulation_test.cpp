// The MPM time loop without the command line (kernels/mpm/simulation): the snapshots it hands to
// its hook and when, the progress after every step, the checks it ends with, and a stop flag
// raised before the run or part way through it.
#include <atomic>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "kernels/mpm/simulation.hpp"

using namespace suite;
using namespace suite::mpm;

namespace {

mpm::Setup small() {
    mpm::Setup s;
    s.mesh = "box:4,4,4";
    s.particles = "sorted";
    s.sort_every = 3;
    return s;
}

}  // namespace

TEST(MpmSimulation, SnapshotsAtZeroEveryKAndTheLastStepWithTheChecksPassed) {
    const mpm::Setup setup = small();
    State st = build(setup);
    SimulationSettings run;
    run.steps = 12;
    run.vtk_every = 5;
    std::vector<std::string> names;
    std::vector<std::uint64_t> progressed;
    SimulationHooks hooks;
    hooks.snapshot = [&names](const std::string& name, const std::string& vtu) {
        names.push_back(name);
        EXPECT_NE(vtu.find("<VTKFile"), std::string::npos);
    };
    hooks.progress = [&progressed](const State& now, double front, double stepping_s) {
        progressed.push_back(now.steps);
        EXPECT_GT(front, 0);
        EXPECT_GE(stepping_s, 0);
    };
    const Outcome r = simulate(st, setup, run, hooks);
    EXPECT_TRUE(r.passed()) << r.failure;
    EXPECT_EQ(r.steps_done, 12u);
    EXPECT_EQ(st.steps, 12u);
    EXPECT_EQ(names, (std::vector<std::string>{"particles_000000.vtu", "particles_000005.vtu", "particles_000010.vtu",
                                               "particles_000012.vtu"}));
    EXPECT_EQ(r.snapshot_steps, (std::vector<std::uint64_t>{0, 5, 10, 12}));
    EXPECT_EQ(snapshot_count(12, 5), 4u);
    EXPECT_EQ(snapshot_count(10, 5), 3u);
    EXPECT_EQ(snapshot_count(10, 0), 0u);
    EXPECT_EQ(progressed.size(), 12u);
    ASSERT_EQ(r.rows.size(), 13u) << "step 0 and each step";
    ASSERT_EQ(r.checks.size(), 4u);
    for (const auto& c : r.checks) EXPECT_TRUE(c.passed) << c.name << ": " << c.detail;
    EXPECT_EQ(r.mass_final, r.mass_initial) << "each particle's mass is its own, bit for bit";
    EXPECT_LE(r.nodal_error, 1e-12);
    EXPECT_EQ(r.signal, 0);
}

TEST(MpmSimulation, AStopFlagEndsTheRunBeforeTheNextStepAndKeepsTheLastState) {
    const mpm::Setup setup = small();
    State st = build(setup);
    std::atomic<int> stop{0};
    SimulationSettings run;
    run.steps = 1000;
    run.vtk_every = 100;
    run.stop = &stop;
    std::vector<std::uint64_t> snapshots;
    SimulationHooks hooks;
    hooks.snapshot = [&](const std::string&, const std::string&) { snapshots.push_back(st.steps); };
    hooks.progress = [&stop](const State& now, double, double) {
        if (now.steps == 7) stop.store(15);  // as the frame's handler would, mid-run
    };
    const Outcome r = simulate(st, setup, run, hooks);
    EXPECT_EQ(r.signal, 15);
    EXPECT_EQ(r.steps_done, 7u);
    EXPECT_EQ(snapshots, (std::vector<std::uint64_t>{0, 7})) << "the state it stopped in is kept";
    EXPECT_TRUE(r.passed()) << r.failure;

    State fresh = build(setup);
    std::atomic<int> early{2};
    run.stop = &early;
    const Outcome none = simulate(fresh, setup, run, hooks);
    EXPECT_EQ(none.steps_done, 0u);
    EXPECT_EQ(none.signal, 2);
}

TEST(MpmSimulation, SnapshotsWithoutAHookAreAProgrammingError) {
    const mpm::Setup setup = small();
    State st = build(setup);
    SimulationSettings run;
    run.steps = 1;
    run.vtk_every = 1;
    EXPECT_THROW(simulate(st, setup, run, SimulationHooks{}), std::logic_error);
    run.vtk_every = 0;
    EXPECT_TRUE(simulate(st, setup, run, SimulationHooks{}).passed());
}
