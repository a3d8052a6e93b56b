// `suite compare` and `suite check` on the committed fixture results (real runs on the
// development VM, tests/fixtures/results/), and on copies changed in known ways: a regression
// must be caught, an improvement reported, noise allowed for, and bad input refused with exit 2.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>

#include "harness/common/stats.hpp"
#include "harness/results/check.hpp"
#include "harness/results/context_fields.hpp"
#include "harness/results/result_file.hpp"
#include "tests/process.hpp"
#include "tests/results/result_fixtures.hpp"

using namespace suite;
using namespace suite::test;
using nlohmann::json;

namespace {

// The record of `doc` for kernel/pattern/size/threads.
json& record(json& doc, const std::string& kernel, const std::string& pattern, std::uint64_t size, int threads) {
    for (auto& r : doc["results"])
        if (r["kernel"] == kernel && r["pattern"] == pattern && r["size"]["requested"] == size &&
            r["threads"] == threads)
            return r;
    throw std::runtime_error("no such record in the fixture");
}

// Makes a bandwidth record `factor` times slower: every sample and every rate.
void slow_down(json& r, double factor) {
    for (auto& s : r["time_s"]["samples"]) s = s.get<double>() * factor;
    for (const char* k : {"min", "median", "max", "mean"}) r["time_s"][k] = r["time_s"][k].get<double>() * factor;
    for (const char* kind : {"stream", "hardware_estimate"})
        for (const char* k : {"best", "median"})
            r["bandwidth_gbps"][kind][k] = r["bandwidth_gbps"][kind][k].get<double>() / factor;
}

void expect_one_line_error(const Outcome& r, const std::string& needle) {
    EXPECT_EQ(r.status, 2) << describe(r);
    EXPECT_EQ(r.err.rfind("suite: error: ", 0), 0u) << describe(r);
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << describe(r);
    EXPECT_NE(r.err.find(needle), std::string::npos) << "stderr lacks '" << needle << "'\n" << describe(r);
}

}  // namespace

TEST(Compare, TwoBuildsSideBySideWithContextDifferencesAndGeometricMeans) {
    Outcome r = run_suite({"compare", fixture("vm-native.json"), fixture("vm-x86-64-v3.json")});
    ASSERT_EQ(r.status, 0) << describe(r);
    // The context differences come before the table, and name both builds' flags.
    const auto ctx = r.out.find("Context differences"), table = r.out.find("point ");
    ASSERT_NE(ctx, std::string::npos) << r.out;
    EXPECT_LT(ctx, table);
    EXPECT_NE(r.out.find("compiler_flags"), std::string::npos);
    EXPECT_NE(r.out.find("-march=native"), std::string::npos);
    EXPECT_NE(r.out.find("-march=x86-64-v3"), std::string::npos);
    EXPECT_EQ(r.out.find("cpu_model "), std::string::npos) << "same CPU: not a difference\n" << r.out;
    EXPECT_NE(r.out.find("126 point(s) of [1] found"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("add random 64MiB t=2 compact/local"), std::string::npos);
    for (const char* k : {"\ncopy ", "\ntriad ", "\nadd "})
        EXPECT_NE(r.out.find(k, r.out.find("Geometric mean")), std::string::npos) << k;
}

TEST(Compare, AFileAgainstItselfIsOneEverywhere) {
    Outcome r = run_suite({"compare", fixture("vm-native.json"), fixture("vm-native.json"), "--format=markdown"});
    ASSERT_EQ(r.status, 0) << describe(r);
    EXPECT_NE(r.out.find("| point | figure |"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("### Geometric mean per kernel"), std::string::npos);
    EXPECT_NE(r.out.find("none: the same CPU"), std::string::npos);
    std::size_t ones = 0;
    for (std::size_t at = 0; (at = r.out.find("| 1.000x", at)) != std::string::npos; ++at) ++ones;
    EXPECT_EQ(ones, 126u + 3u) << "every point and every kernel's mean is 1.000x";
}

TEST(Compare, RatiosArePerformanceWhicheverWayTheFigureGoes) {
    TempDir dir;
    json doc = load(fixture("vm-native-latency.json"));
    json slower = doc;
    for (auto& r : slower["results"])
        for (const char* k : {"best", "median"}) r["latency_ns"][k] = r["latency_ns"][k].get<double>() * 2;
    save(slower, dir.file("slower.json"));
    Outcome r = run_suite({"compare", fixture("vm-native-latency.json"), dir.file("slower.json")});
    ASSERT_EQ(r.status, 0) << describe(r);
    EXPECT_NE(r.out.find("0.500x"), std::string::npos) << "twice the latency is half the performance\n" << r.out;
    EXPECT_EQ(r.out.find("2.000x"), std::string::npos);
}

TEST(Compare, BadInputIsOneLineAndExitTwo) {
    TempDir dir;
    expect_one_line_error(run_suite({"compare", fixture("vm-native.json"), fixture("vm-native-latency.json")}),
                          "no point of");
    expect_one_line_error(run_suite({"compare", fixture("vm-native.json")}), "at least two");
    expect_one_line_error(run_suite({"compare", fixture("vm-native.json"), dir.file("missing.json")}),
                          "missing.json: cannot read it");
    expect_one_line_error(run_suite({"compare", fixture("vm-native.json"), fixture("vm-native.json"), "--format=html"}),
                          "markdown");
    json future = load(fixture("vm-native.json"));
    future["schema_version"] = 3;
    save(future, dir.file("v3.json"));
    expect_one_line_error(run_suite({"compare", fixture("vm-native.json"), dir.file("v3.json")}), "schema_version 3");
    save(json{{"context", json::object()}, {"benchmarks", json::array()}}, dir.file("gb.json"));
    expect_one_line_error(run_suite({"compare", fixture("vm-native.json"), dir.file("gb.json")}), "Google Benchmark");
}

TEST(Check, JudgeAllowsTheToleranceAndTheNoiseOfBothRuns) {
    const Measure base{"latency", "ns/load", Direction::lower_is_better, 100, 100, 0.03, {}, NAN};
    Measure run = base;
    run.median = 115;  // 15 % worse; allowed 10 % + sqrt(0.03^2 + 0.03^2) = 14.2 %
    EXPECT_EQ(judge(base, run, 0.10).verdict, Verdict::regressed);
    EXPECT_NEAR(judge(base, run, 0.10).allowed, 0.10 + std::sqrt(2 * 0.03 * 0.03), 1e-12);
    run.median = 112;
    EXPECT_EQ(judge(base, run, 0.10).verdict, Verdict::unchanged);
    run.noise = 0.2;  // a noisy run widens the threshold
    run.median = 125;
    EXPECT_EQ(judge(base, run, 0.10).verdict, Verdict::unchanged);
    // Higher is better: half the bandwidth is 100 % worse; twice is an improvement.
    const Measure bw{"bandwidth", "GB/s", Direction::higher_is_better, 10, 10, 0, {}, NAN};
    Measure half = bw, twice = bw;
    half.median = 5;
    twice.median = 20;
    EXPECT_EQ(judge(bw, half, 0.10).verdict, Verdict::regressed);
    EXPECT_NEAR(judge(bw, half, 0.10).worse_by, 1.0, 1e-12);
    EXPECT_EQ(judge(bw, twice, 0.10).verdict, Verdict::improved);
    // A count that was 0 and is no longer 0 is worse, whatever the tolerance.
    const Measure zero{"callgrind LL misses", "per call", Direction::lower_is_better, 0, 0, 0, {}, NAN};
    Measure some = zero;
    some.median = 3;
    EXPECT_EQ(judge(zero, some, 10.0).verdict, Verdict::regressed);
    EXPECT_EQ(judge(zero, zero, 0.0).verdict, Verdict::unchanged);
}

TEST(Check, RobustSpreadIgnoresOutliers) {
    std::vector<double> s(100, 1.0);
    for (std::size_t i = 0; i < s.size(); ++i) s[i] += (i % 2 ? 0.01 : -0.01);
    const double calm = robust_relative_spread(s);
    EXPECT_NEAR(calm, 1.4826 * 0.01, 1e-9);
    s[0] = 50;  // one repetition hit by an interrupt: the median moves by one sample at most
    EXPECT_NEAR(robust_relative_spread(s), calm, 0.02 * calm);
    EXPECT_EQ(robust_relative_spread({1.0}), 0.0);
}

TEST(Check, ARunAgainstItselfPasses) {
    Outcome r = run_suite({"check", "--baseline", fixture("vm-native.json"), fixture("vm-native.json")});
    EXPECT_EQ(r.status, 0) << describe(r);
    EXPECT_NE(r.out.find("126 point(s) compared, 126 figure(s): 0 regressed, 0 improved"), std::string::npos) << r.out;
}

TEST(Check, ASlowerPointIsARegressionAndAFasterOneAnImprovement) {
    TempDir dir;
    json doc = load(fixture("vm-native.json"));
    slow_down(record(doc, "add", "random", 64ULL << 20, 1), 2.0);
    slow_down(record(doc, "copy", "sequential", 16ULL << 20, 2), 0.5);
    save(doc, dir.file("run.json"));
    Outcome r = run_suite(
        {"check", "--baseline", fixture("vm-native.json"), dir.file("run.json"), "--markdown=" + dir.file("gate.md")});
    EXPECT_EQ(r.status, 1) << describe(r);
    EXPECT_NE(r.out.find("REGRESSED  add random 64MiB t=1 compact/local"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("improved   copy sequential 16MiB t=2 compact/local"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("1 regressed, 1 improved, 124 within the threshold"), std::string::npos) << r.out;
    // The change is the figure's own, signed: half the bandwidth is -50 %, twice is +100 %.
    const auto row = [&](const std::string& start) {
        return r.out.substr(r.out.find(start), r.out.find('\n', r.out.find(start)) - r.out.find(start));
    };
    EXPECT_NE(row("REGRESSED  add random 64MiB").find("-50.0%"), std::string::npos) << r.out;
    EXPECT_NE(row("improved   copy sequential 16MiB").find("+100.0%"), std::string::npos) << r.out;
    EXPECT_EQ(r.out.find("worse"), std::string::npos) << r.out;
    const std::string md = slurp(dir.file("gate.md"));
    EXPECT_NE(md.find("### suite check: **1 regression(s)**, 1 improvement(s)"), std::string::npos) << md;
    EXPECT_NE(md.find("| REGRESSED | `add random 64MiB t=1 compact/local` |"), std::string::npos) << md;
    // A generous tolerance lets it through.
    Outcome lax =
        run_suite({"check", "--baseline", fixture("vm-native.json"), dir.file("run.json"), "--tolerance=150%"});
    EXPECT_EQ(lax.status, 0) << describe(lax);
}

TEST(Check, AFailedVerificationIsARegression) {
    TempDir dir;
    json doc = load(fixture("vm-native.json"));
    record(doc, "triad", "sequential", 16ULL << 10, 1)["verification"]["passed"] = false;
    save(doc, dir.file("run.json"));
    Outcome r = run_suite({"check", "--baseline", fixture("vm-native.json"), dir.file("run.json")});
    EXPECT_EQ(r.status, 1) << describe(r);
    EXPECT_NE(r.out.find("failed verification"), std::string::npos) << r.out;
}

TEST(Check, AnUnstablePointIsInconclusiveNeitherARegressionNorAPass) {
    TempDir dir;
    const std::string why = "other tasks took 48% of the team's CPUs (over 10%)";
    json base = load(fixture("vm-native.json"));
    json run = base;
    // Twice as slow in the run, where the run says the machine was busy: not a regression.
    slow_down(record(run, "add", "random", 64ULL << 20, 1), 2.0);
    record(run, "add", "random", 64ULL << 20, 1)["stability"] = {{"unstable", true}, {"reasons", {why}}};
    // Unchanged, but the baseline was busy there: not a pass either.
    record(base, "copy", "sequential", 16ULL << 20, 2)["stability"] = {
        {"unstable", true}, {"reasons", {"the repetitions spread 23% (over 10%)"}}};
    save(base, dir.file("base.json"));
    save(run, dir.file("run.json"));
    Outcome r = run_suite(
        {"check", "--baseline", dir.file("base.json"), dir.file("run.json"), "--markdown=" + dir.file("gate.md")});
    EXPECT_EQ(r.status, 0) << describe(r);
    EXPECT_NE(r.out.find("inconclusive  add random 64MiB t=1 compact/local"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("inconclusive: add random 64MiB t=1 compact/local: unstable in the run: " + why),
              std::string::npos)
        << r.out;
    EXPECT_NE(
        r.out.find(
            "inconclusive: copy sequential 16MiB t=2 compact/local: unstable in the baseline: the repetitions spread"),
        std::string::npos)
        << r.out;
    EXPECT_NE(r.out.find("0 regressed, 0 improved, 124 within the threshold, 2 inconclusive"), std::string::npos)
        << r.out;
    EXPECT_NE(slurp(dir.file("gate.md")).find("no regression, 2 inconclusive"), std::string::npos);
    // A stable slow point beside them still fails the gate.
    slow_down(record(run, "triad", "sequential", 16ULL << 10, 1), 2.0);
    save(run, dir.file("run.json"));
    Outcome bad = run_suite({"check", "--baseline", dir.file("base.json"), dir.file("run.json")});
    EXPECT_EQ(bad.status, 1) << describe(bad);
    // A failed verification is a regression however busy the machine was.
    record(run, "add", "random", 64ULL << 20, 1)["verification"]["passed"] = false;
    save(run, dir.file("run.json"));
    EXPECT_NE(
        run_suite({"check", "--baseline", dir.file("base.json"), dir.file("run.json")}).out.find("failed verification"),
        std::string::npos);
    // A stability block that is not what suite writes is refused, naming the field.
    record(run, "add", "random", 64ULL << 20, 1)["stability"] = {{"unstable", "yes"}};
    save(run, dir.file("run.json"));
    expect_one_line_error(run_suite({"check", "--baseline", dir.file("base.json"), dir.file("run.json")}),
                          ".stability.unstable");
}

TEST(Check, CountersAndEnergyAreGatedLowerIsBetter) {
    TempDir dir;
    const std::string base = fixture("vm-native-HANDMADE-counters-energy.json");
    json doc = load(base);
    json& r0 = doc["results"][0];
    for (auto& e : r0["counters"]["events"])
        if (e["name"] == "cycles") e["per_element"] = e["per_element"].get<double>() * 1.5;
    json& r1 = doc["results"][1];
    for (const char* stat : {"min", "median", "max"})  // a whole distribution three times higher
        r1["energy"]["domains"][0]["joules_per_call"][stat] =
            r1["energy"]["domains"][0]["joules_per_call"][stat].get<double>() * 3;
    save(doc, dir.file("run.json"));
    Outcome r = run_suite({"check", "--baseline", base, dir.file("run.json")});
    EXPECT_EQ(r.status, 1) << describe(r);
    EXPECT_NE(r.out.find("counter cycles per element"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("energy package-0 J/call"), std::string::npos) << r.out;
    // Absent blocks (older files) are simply not compared: the plain fixture gates bandwidth only.
    Outcome plain = run_suite({"check", "--baseline", fixture("vm-native.json"), base});
    EXPECT_EQ(plain.status, 0) << describe(plain);
}

TEST(Check, UnusableInputIsExitTwo) {
    TempDir dir;
    expect_one_line_error(
        run_suite({"check", "--baseline", fixture("vm-native-latency.json"), fixture("vm-native.json")}),
        "none of the");
    expect_one_line_error(run_suite({"check", fixture("vm-native.json")}), "--baseline");
    expect_one_line_error(
        run_suite({"check", "--baseline", fixture("vm-native.json"), fixture("vm-native.json"), "--tolerance=lots"}),
        "--tolerance");
    json doc = load(fixture("vm-native.json"));
    doc["complete"] = false;
    save(doc, dir.file("interrupted.json"));
    expect_one_line_error(run_suite({"check", "--baseline", fixture("vm-native.json"), dir.file("interrupted.json")}),
                          "interrupted");
    { std::ofstream(dir.file("empty.json")); }
    expect_one_line_error(run_suite({"check", "--baseline", dir.file("empty.json"), fixture("vm-native.json")}),
                          "empty");
    expect_one_line_error(run_suite({"check", "--baseline", fixture("vm-native.json"), dir.path().string()}),
                          "is a directory");
    // --markdown into a directory that does not exist: exit 2, not 1 (1 means "regressed").
    expect_one_line_error(run_suite({"check", "--baseline", fixture("vm-native.json"), fixture("vm-native.json"),
                                     "--markdown=" + dir.file("no/such/dir/gate.md")}),
                          "--markdown");
}

TEST(Check, TheCommittedBaselinesAreReadable) {
    for (const char* name : {"ci.json", "ci-deterministic.json"}) {
        const std::string path = std::string(SUITE_SOURCE_DIR) + "/results/baseline/" + name;
        Outcome r = run_suite({"check", "--baseline", path, path, "--tolerance=0"});
        EXPECT_EQ(r.status, 0) << name << "\n" << describe(r);
    }
    const ResultFile det = load_result_file(std::string(SUITE_SOURCE_DIR) + "/results/baseline/ci-deterministic.json");
    ASSERT_FALSE(det.points.empty());
    for (const auto& p : det.points) {
        EXPECT_TRUE(p.under_callgrind);
        ASSERT_EQ(p.measures.size(), 3u);
        EXPECT_EQ(p.measures[0].name, "callgrind instructions");
        EXPECT_EQ(p.measures[0].noise, 0.0);
    }
}
