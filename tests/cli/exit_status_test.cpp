// The exit status of a run, in process (execute_plan, as `suite run` calls it): 3 when an
// iterative solver did not converge, before 1 for a failed verification, with one error line
// each; and the console table prints a kernel's facts under its row. The binary has no kernel
// with a solver that can be made to fail, so the test-only one (tests/kernel/test_solver_kernel.cpp)
// runs here.
#include <gtest/gtest.h>

#include <map>
#include <string>
#include <utility>
#include <vector>

#include "app/suite/run.hpp"
#include "harness/measure/plan.hpp"
#include "tests/kernel/test_solver_kernel.hpp"

using namespace suite;

namespace {

const Topology& topology() {
    static const Topology topo = Topology::load();
    return topo;
}

// test-solve's jacobi strategy on one thread, 1024 rows, 2 repetitions, one point per `params`.
Plan solver_plan(const std::vector<std::map<std::string, std::string>>& params, bool quiet = true) {
    RunOptions o;
    o.kernels = suite::test::solver_kernel;
    o.strategies = "jacobi";
    o.size = "1024";
    o.threads = "1";
    o.reps = 2;
    o.quiet = quiet;
    Plan plan;
    for (const auto& p : params) {
        o.params = p;
        Plan one = make_plan(o, topology());
        if (plan.points.empty())
            plan = std::move(one);
        else
            plan.points.insert(plan.points.end(), one.points.begin(), one.points.end());
    }
    return plan;
}

struct Ran {
    int status;
    std::string out, err;
};

Ran run(Plan&& plan) {
    ::testing::internal::CaptureStdout();
    ::testing::internal::CaptureStderr();
    CommandFrame frame("suite");
    const int status = execute_plan(plan, topology(), {"suite"}, frame);
    std::string out = ::testing::internal::GetCapturedStdout();
    return {status, out, ::testing::internal::GetCapturedStderr()};
}

}  // namespace

TEST(ExitStatus, ASolverThatDoesNotConvergeIsThree) {
    const Ran r = run(solver_plan({{{"delta", "1.5"}}}));
    EXPECT_EQ(r.status, 3) << r.err;
    EXPECT_NE(r.err.find("suite: error: test-solve-jacobi natural 1024: solver failed: no convergence after"),
              std::string::npos)
        << r.err;
    EXPECT_TRUE(r.out.empty()) << r.out;
}

TEST(ExitStatus, ThreeWinsOverOneWhicheverComesFirst) {
    // --wrong=1 corrupts the answer: a failed verification, 1 on its own.
    const Ran wrong = run(solver_plan({{{"wrong", "1"}}}));
    EXPECT_EQ(wrong.status, 1) << wrong.err;
    EXPECT_NE(wrong.err.find("test-solve-jacobi natural 1024 failed verification"), std::string::npos) << wrong.err;
    for (const auto& order : {std::vector<std::map<std::string, std::string>>{{{"wrong", "1"}}, {{"delta", "1.5"}}},
                              std::vector<std::map<std::string, std::string>>{{{"delta", "1.5"}}, {{"wrong", "1"}}}}) {
        const Ran r = run(solver_plan(order));
        EXPECT_EQ(r.status, 3) << r.err;
        EXPECT_NE(r.err.find("solver failed"), std::string::npos) << r.err;
        EXPECT_NE(r.err.find("failed verification"), std::string::npos) << r.err;
    }
    EXPECT_EQ(run(solver_plan(std::vector<std::map<std::string, std::string>>(1))).status, 0);
}

TEST(ExitStatus, TheTableShowsFactsUnderTheRowUnlessQuiet) {
    const Ran shown = run(solver_plan({{{"delta", "0.25"}}}, false));
    EXPECT_EQ(shown.status, 0) << shown.err;
    EXPECT_NE(shown.out.find("test-solve-jacobi"), std::string::npos) << shown.out;
    EXPECT_NE(shown.out.find("\n        x0=0.8, iterations="), std::string::npos) << shown.out;
    EXPECT_TRUE(run(solver_plan({{{"delta", "0.25"}}}, true)).out.empty());
}

TEST(ExitStatus, DryRunListsTheParameters) {
    Plan plan = solver_plan({{{"delta", "0.25"}}});
    plan.dry_run = true;
    const Ran r = run(std::move(plan));
    EXPECT_EQ(r.status, 0);
    EXPECT_NE(r.out.find("test-solve-jacobi natural 1024 threads=1 delta=0.25 tol=1e-08 wrong=0"), std::string::npos)
        << r.out;
}
