// In-process tests of what application kernels declare for planning: --strategy (variants picked
// as --phase picks sfc-build's), default and single-thread variants, and parameters (--delta,
// --tol) with their defaults and strict values. The kernel is tests/kernel/test_solver_kernel.cpp.
#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <string>
#include <vector>

#include "app/suite/parse.hpp"
#include "app/suite/run.hpp"
#include "harness/common/units.hpp"
#include "harness/measure/plan.hpp"
#include "tests/kernel/test_solver_kernel.hpp"
#include "tests/synthetic_topology.hpp"

using namespace suite;
using suite::testing::two_socket;

namespace {

RunOptions solver_options() {
    RunOptions o;
    o.kernels = suite::test::solver_kernel;
    o.size = "1000";
    o.threads = "1-2";
    return o;
}

// {variant, threads} of every point.
std::multiset<std::pair<std::string, int>> variants_and_threads(const Plan& plan) {
    std::multiset<std::pair<std::string, int>> out;
    for (const auto& p : plan.points) out.insert({p.variant, p.threads});
    return out;
}

// make_plan's UsageError, one line, with every `needles` in it.
void expect_usage_error(const RunOptions& o, const std::vector<std::string>& needles) {
    try {
        make_plan(o, two_socket());
        ADD_FAILURE() << "accepted; expected an error with '" << needles.front() << "'";
    } catch (const UsageError& e) {
        const std::string what = e.what();
        EXPECT_EQ(what.find('\n'), std::string::npos) << what;
        for (const auto& n : needles) EXPECT_NE(what.find(n), std::string::npos) << "'" << n << "' not in: " << what;
    }
}

}  // namespace

TEST(PlanVariants, DefaultVariantsRunAndSingleThreadOnesOnlyOnOneThread) {
    // default_variants {jacobi, serial}; serial is a single-thread variant: not planned for 2.
    const Plan plan = make_plan(solver_options(), two_socket());
    EXPECT_EQ(variants_and_threads(plan),
              (std::multiset<std::pair<std::string, int>>{{"jacobi", 1}, {"jacobi", 2}, {"serial", 1}}));
}

TEST(PlanVariants, StrategyPicksVariantsInTheOrderGiven) {
    RunOptions o = solver_options();
    o.strategies = "atomic,jacobi";
    const Plan plan = make_plan(o, two_socket());
    ASSERT_EQ(plan.points.size(), 4u);
    EXPECT_EQ(plan.points[0].variant, "atomic");
    EXPECT_EQ(plan.points[2].variant, "jacobi");
    // A single-thread strategy named with --threads=1 runs; with threads left to their default
    // (1 and all) it runs on the one thread.
    o.strategies = "serial";
    o.threads = "1";
    EXPECT_EQ(variants_and_threads(make_plan(o, two_socket())),
              (std::multiset<std::pair<std::string, int>>{{"serial", 1}}));
    o.threads = "";
    EXPECT_EQ(variants_and_threads(make_plan(o, two_socket())),
              (std::multiset<std::pair<std::string, int>>{{"serial", 1}}));
}

TEST(PlanVariants, ASingleThreadStrategyNamedWithMoreThreadsIsRefused) {
    RunOptions o = solver_options();
    o.strategies = "jacobi,serial";
    expect_usage_error(o,
                       {"--strategy=jacobi,serial", "'serial'", "runs on one thread", "--threads=1-2", "--threads=1"});
    // Defaulted, the single-thread variants are left out; when nothing is left, that is said.
    o.strategies = "serial";
    o.threads = "2";
    expect_usage_error(o, {"'serial'", "one thread"});
    o.strategies = "";
    EXPECT_EQ(variants_and_threads(make_plan(o, two_socket())),
              (std::multiset<std::pair<std::string, int>>{{"jacobi", 2}}));
}

TEST(PlanVariants, StrategyErrorsNameTheKernelAndWhatIsAccepted) {
    RunOptions o = solver_options();
    o.strategies = "jacobbi";
    expect_usage_error(o, {"kernel 'test-solve' has no strategy 'jacobbi'", "did you mean 'jacobi'?",
                           "strategies: jacobi, serial, atomic"});
    o.strategies = "jacobi,jacobi";
    expect_usage_error(o, {"--strategy=jacobi,jacobi", "'jacobi' twice"});
    o.strategies = "jacobi,";
    expect_usage_error(o, {"--strategy=jacobi,", "empty name"});
    // Kernels without strategies, with and without another variant option.
    o.strategies = "jacobi";
    o.kernels = "add";
    o.size = "64KiB";
    expect_usage_error(
        o, {"kernel 'add' has no strategies, so --strategy does not apply", "kernels with strategies:", "test-solve"});
    o.kernels = "sfc-build";
    o.size = "1536";
    expect_usage_error(o, {"kernel 'sfc-build' has no strategies", "(it takes --phase)"});
    // --phase is for phases: the strategy kernel refuses it the same way.
    o.strategies = "";
    o.phases = "keys";
    o.kernels = suite::test::solver_kernel;
    o.size = "1000";
    expect_usage_error(
        o, {"kernel 'test-solve' has no phases", "(it takes --strategy)", "kernels with phases: sfc-build"});
}

TEST(PlanVariants, PhaseStillPicksSfcBuildPhases) {
    RunOptions o;
    o.kernels = "sfc-build";
    o.size = "1536";
    o.threads = "1";
    o.phases = "keys,all";
    const Plan plan = make_plan(o, two_socket());
    ASSERT_EQ(plan.points.size(), 2u);
    EXPECT_EQ(plan.points[0].variant, "keys");
    EXPECT_EQ(plan.points[1].variant, "");
    EXPECT_TRUE(plan.points[0].params.empty());
    o.phases = "";  // no default_variants: the plain kernel
    ASSERT_EQ(make_plan(o, two_socket()).points.size(), 1u);
    EXPECT_EQ(make_plan(o, two_socket()).points[0].variant, "");
}

TEST(PlanParams, DefaultsAreFilledAndGivenValuesOverrideThem) {
    RunOptions o = solver_options();
    Plan plan = make_plan(o, two_socket());
    ASSERT_FALSE(plan.points.empty());
    for (const auto& p : plan.points) EXPECT_EQ(p.params, (Params{{"delta", 0.5}, {"tol", 1e-8}, {"wrong", 0.0}}));
    o.params = {{"delta", "-0.25"}, {"tol", "1E-10"}};
    plan = make_plan(o, two_socket());
    for (const auto& p : plan.points) EXPECT_EQ(p.params, (Params{{"delta", -0.25}, {"tol", 1e-10}, {"wrong", 0.0}}));
    // A kernel beside it that declares none: the option applies (one selected kernel takes it),
    // and that kernel's points have no parameters.
    o.kernels = std::string("sfc-build,") + suite::test::solver_kernel;
    o.size = "1536";
    o.threads = "1";
    o.params = {{"delta", "0.1"}};
    plan = make_plan(o, two_socket());
    ASSERT_EQ(plan.points.size(), 3u);  // sfc-build; test-solve jacobi and serial
    for (const auto& p : plan.points) {
        if (p.kernel->info.name == "sfc-build")
            EXPECT_TRUE(p.params.empty());
        else
            EXPECT_EQ(p.params.at("delta"), ParamValue(0.1));
    }
}

TEST(PlanParams, BadValuesAreOneLineNamingTheOption) {
    RunOptions o = solver_options();
    for (const char* bad :
         {"abc", "", "inf", "-inf", "nan", "NaN", "1e999", "0x10", " 1", "1 ", "1.5.2", "1e", ".", "+", "5%", "1,5"}) {
        SCOPED_TRACE(bad);
        o.params = {{"delta", bad}};
        expect_usage_error(o, {"--delta=" + std::string(bad) + ":", "finite number"});
    }
    // The kernel's own range check (KernelEntry::validate).
    o.params = {{"delta", "-2"}};
    expect_usage_error(o, {"--delta=-2", "above -1"});
    o.params = {{"tol", "0"}};
    expect_usage_error(o, {"--tol=0", "between 0 and 1"});
}

TEST(PlanParams, AParameterNoSelectedKernelTakesIsRefused) {
    RunOptions o;
    o.kernels = "add";
    o.size = "64KiB";
    o.params = {{"tol", "1e-6"}};
    expect_usage_error(o, {"--tol does not apply to kernel 'add'", "kernels that take it:", "test-solve"});
    o.kernels = "add,triad";
    expect_usage_error(o, {"--tol does not apply to kernels 'add', 'triad'"});
    o.params = {{"nonesuch", "1"}};
    expect_usage_error(o, {"--nonesuch", "no kernel takes"});
}

// The command line: one option per declared parameter, collected from the registry before
// parsing; the text is kept as typed for make_plan.
TEST(RunOptionsCli, ParameterAndStrategyOptionsAreDeclared) {
    CLI::App app;
    RunOptions o;
    setup_run_options(app, o);
    for (const char* name : {"--delta", "--tol", "--wrong", "--strategy", "--phase"})
        EXPECT_NE(app.get_option_no_throw(name), nullptr) << name;
    ASSERT_TRUE(parse_command_line(app, "suite",
                                   {"--kernel=test-solve", "--strategy=jacobi", "--delta=0.125", "--tol", "1e-9"}));
    EXPECT_EQ(o.strategies, "jacobi");
    EXPECT_EQ(o.params, (std::map<std::string, std::string>{{"delta", "0.125"}, {"tol", "1e-9"}}));
    // An empty value is refused before parsing, as for every option.
    CLI::App app2;
    RunOptions o2;
    setup_run_options(app2, o2);
    EXPECT_THROW(parse_command_line(app2, "suite", {"--delta="}), UsageError);
}

TEST(ParseFinite, AcceptsDecimalNumbersOnly) {
    EXPECT_EQ(parse_finite("0.05", "--x"), 0.05);
    EXPECT_EQ(parse_finite("-2", "--x"), -2.0);
    EXPECT_EQ(parse_finite("+3.5", "--x"), 3.5);
    EXPECT_EQ(parse_finite("1e-8", "--x"), 1e-8);
    EXPECT_EQ(parse_finite("2.5E+3", "--x"), 2500.0);
    EXPECT_EQ(parse_finite(".5", "--x"), 0.5);
    EXPECT_EQ(parse_finite("5.", "--x"), 5.0);
    for (const char* bad : {"", "-", "e5", "1e+", "infinity", "0x1p3", "1_000", "1e400"})
        EXPECT_THROW(parse_finite(bad, "--x"), UsageError) << bad;
    EXPECT_EQ(format_number(0.05), "0.05");
    EXPECT_EQ(format_number(1e-8), "1e-08");
    EXPECT_EQ(format_number(12), "12");
    EXPECT_EQ(format_number(100000), "100000");
    EXPECT_EQ(format_number(-0.25), "-0.25");
    EXPECT_EQ(format_number(1e20), "1e+20");
}

// fem-spmv's plain kernel is CSR, named csr under --strategy: csr plans variant "" (the records keep
// the kernel's own name), symmetric its own; without --strategy the plain kernel alone.
TEST(PlanVariants, APlainKernelNamedUnderTheOptionIsPlannedAsThePlainKernel) {
    RunOptions o;
    o.kernels = "fem-spmv";
    o.threads = "1";
    o.mesh = "disk:refine=2";
    EXPECT_EQ(variants_and_threads(make_plan(o, two_socket())), (std::multiset<std::pair<std::string, int>>{{"", 1}}));
    o.strategies = "symmetric,csr";
    EXPECT_EQ(variants_and_threads(make_plan(o, two_socket())),
              (std::multiset<std::pair<std::string, int>>{{"symmetric", 1}, {"", 1}}));
    o.strategies = "csv";
    expect_usage_error(
        o, {"kernel 'fem-spmv' has no strategy 'csv'", "did you mean 'csr'?", "strategies: csr, symmetric"});
}
