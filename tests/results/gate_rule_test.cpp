// The decision rule of `suite check` (a minimum effect and a rank test on the repetitions, four
// outcomes), on hand-made figures, on simulated A/A and shifted runs, and end to end: the
// comparisons that must be refused (another machine, another build or huge-page setting) and
// the ones that must be allowed ("all threads" on machines of different core counts).
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>
#include <random>

#include "harness/results/check.hpp"
#include "harness/results/result_file.hpp"
#include "tests/process.hpp"
#include "tests/results/result_fixtures.hpp"

using namespace suite;
using namespace suite::test;
using nlohmann::json;

namespace {

Measure bandwidth(std::vector<double> samples) {
    Measure m{"bandwidth", "GB/s", Direction::higher_is_better, 0, 0, 0, std::move(samples), NAN};
    std::vector<double> s = m.samples;
    std::sort(s.begin(), s.end());
    m.best = s.back();
    m.median = s[s.size() / 2];
    return m;
}

Measure count(const char* name, double per_element, double per_call) {
    return Measure{name, "per element", Direction::lower_is_better, per_element, per_element, 0, {}, per_call};
}

// `reps` repetitions of a figure around `level` with log-normal noise of relative size `noise`.
std::vector<double> draw(std::mt19937_64& rng, double level, double noise, int reps) {
    std::normal_distribution<double> z(0, noise);
    std::vector<double> s;
    for (int i = 0; i < reps; ++i) s.push_back(level * std::exp(z(rng)));
    return s;
}

void expect_one_line_error(const Outcome& r, const std::string& needle) {
    EXPECT_EQ(r.status, 2) << describe(r);
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << describe(r);
    EXPECT_NE(r.err.find(needle), std::string::npos) << "stderr lacks '" << needle << "'\n" << describe(r);
}

}  // namespace

TEST(GateRule, BeyondTheEffectAndSeparatedIsARegressionWithItsPAndInterval) {
    const Measure base = bandwidth({10.0, 10.1, 9.9, 10.2, 9.8});
    const Measure slow = bandwidth({7.0, 7.1, 6.9, 7.2, 6.8});  // -30 %, no overlap
    const Finding f = judge(base, slow, GateRule{});
    EXPECT_EQ(f.verdict, Verdict::regressed);
    EXPECT_TRUE(f.tested);
    EXPECT_NEAR(f.p, 1.0 / 252, 1e-12);  // five against five, fully separated
    EXPECT_LT(f.ratio_high, 0.75);       // the whole interval is a drop of more than a quarter
    EXPECT_GT(f.ratio_low, 0.65);
    EXPECT_EQ(judge(slow, base, GateRule{}).verdict, Verdict::improved);
    // Within the tolerance it is unchanged however significant: 3 % is not a regression at 10 %.
    const Measure close = bandwidth({9.6, 9.65, 9.7, 9.55, 9.5});  // -4 %, below every baseline repetition
    EXPECT_EQ(judge(base, close, GateRule{}).verdict, Verdict::unchanged);
    EXPECT_EQ(judge(base, close, GateRule{0.01}).verdict, Verdict::regressed);
}

TEST(GateRule, AChangeTheRepetitionsCannotTellFromNoiseIsInconclusive) {
    const Measure base = bandwidth({10.0, 6.0, 12.0, 8.0, 11.0});
    const Measure run = bandwidth({8.0, 5.0, 11.0, 7.0, 10.0});  // median -20 %, overlapping
    const Finding f = judge(base, run, GateRule{});
    EXPECT_EQ(f.verdict, Verdict::inconclusive);
    EXPECT_GT(f.p, 0.01);
    EXPECT_NE(f.note.find("Mann-Whitney p"), std::string::npos) << f.note;
    // Three against three can never reach p < 0.01 (the smallest one-sided p is 1/20)...
    const Measure b3 = bandwidth({10.0, 10.1, 9.9}), r3 = bandwidth({5.0, 5.1, 4.9});
    EXPECT_EQ(judge(b3, r3, GateRule{}).verdict, Verdict::inconclusive);
    EXPECT_NEAR(judge(b3, r3, GateRule{}).p, 0.05, 1e-12);
    // ...but a weaker test accepts it.
    GateRule weak;
    weak.alpha = 0.1;
    EXPECT_EQ(judge(b3, r3, weak).verdict, Verdict::regressed);
}

TEST(GateRule, CountsNearZeroAreNotGatedByRatio) {
    // 0 -> 1 context switch a repetition was "infinitely worse" under a plain ratio.
    const Finding f =
        judge(count("counter context-switches", 0, 0), count("counter context-switches", 9.5e-7, 1), GateRule{});
    EXPECT_EQ(f.verdict, Verdict::unchanged);
    EXPECT_NE(f.note.find("not gated by ratio"), std::string::npos);
    // Enough events to mean something: gated as before, from 0 too.
    EXPECT_EQ(judge(count("counter cache-misses", 0, 0), count("counter cache-misses", 0.5, 5000), GateRule{}).verdict,
              Verdict::regressed);
    EXPECT_EQ(
        judge(count("counter cache-misses", 0.1, 1000), count("counter cache-misses", 0.2, 2000), GateRule{}).verdict,
        Verdict::regressed);
    // A figure that is not a count (no count_per_call) is never exempted.
    const Measure lat{"latency", "ns/load", Direction::lower_is_better, 1, 1, 0, {}, NAN};
    Measure lat2 = lat;
    lat2.median = 2;
    EXPECT_EQ(judge(lat, lat2, GateRule{}).verdict, Verdict::regressed);
}

// What the default rule does over many simulated pairs of runs: A/A (both from one
// distribution, 3 % noise, 5 repetitions) must almost never alarm; a 20 % shift must be caught.
TEST(GateRule, SimulatedAAPairsRarelyAlarmAndAKnownShiftIsCaught) {
    std::mt19937_64 rng(20261125);
    int aa_alarms = 0, caught = 0, missed = 0;
    const int pairs = 500;
    for (int i = 0; i < pairs; ++i) {
        const Measure a = bandwidth(draw(rng, 10, 0.03, 5)), b = bandwidth(draw(rng, 10, 0.03, 5));
        aa_alarms += judge(a, b, GateRule{}).verdict != Verdict::unchanged;
        const Verdict v = judge(a, bandwidth(draw(rng, 8, 0.03, 5)), GateRule{}).verdict;  // -20 %
        caught += v == Verdict::regressed;
        missed += v == Verdict::unchanged;
    }
    EXPECT_LE(aa_alarms, pairs / 100) << "A/A pairs judged anything but unchanged";
    EXPECT_GE(caught, pairs * 95 / 100);
    EXPECT_EQ(missed, 0);
}

TEST(GateRule, TheFixturesCarryTheirRepetitionsInTheFiguresUnits) {
    const ResultFile f = load_result_file(fixture("vm-native.json"));
    const Measure& m = f.points.front().measures.front();
    ASSERT_EQ(m.samples.size(), 5u);
    std::vector<double> s = m.samples;
    std::sort(s.begin(), s.end());
    EXPECT_NEAR(s[2], m.median, 1e-9 * m.median);  // the median repetition is the recorded median
    EXPECT_NEAR(s[4], m.best, 1e-9 * m.best);      // and the fastest the best
}

TEST(GateRule, CheckRefusesAnotherBuildOrHugePageSettingUnlessForced) {
    TempDir dir;
    json base = load(fixture("vm-native.json")), run = base;
    for (auto& r : base["results"]) r["hugepages"] = {{"requested", "none"}};
    for (auto& r : run["results"]) r["hugepages"] = {{"requested", "thp"}};
    save(base, dir.file("none.json"));
    save(run, dir.file("thp.json"));
    expect_one_line_error(run_suite({"check", "--baseline", dir.file("none.json"), dir.file("thp.json")}),
                          "hugepages 'none' -> 'thp'");
    Outcome forced = run_suite({"check", "--baseline", dir.file("none.json"), dir.file("thp.json"), "--force"});
    EXPECT_EQ(forced.status, 0) << describe(forced);
    EXPECT_NE(forced.out.find("compared anyway, --force): hugepages"), std::string::npos) << forced.out;
    expect_one_line_error(run_suite({"check", "--baseline", fixture("vm-native.json"), fixture("vm-x86-64-v3.json")}),
                          "compiler_flags");
    // compare lists the difference (it used to say "none") and, one kind of change only, compares.
    Outcome cmp = run_suite({"compare", dir.file("none.json"), dir.file("thp.json")});
    EXPECT_EQ(cmp.status, 0) << describe(cmp);
    EXPECT_NE(cmp.out.find("hugepages  build/setting  none"), std::string::npos) << cmp.out;
    expect_one_line_error(run_suite({"check", "--baseline", dir.file("none.json"), dir.file("none.json"), "--alpha=2"}),
                          "--alpha");
}

TEST(GateRule, CompareMatchesAllThreadsAcrossCoreCountsAndRefusesTwoChangesAtOnce) {
    TempDir dir;
    json small = load(fixture("vm-native.json")), big = small;
    for (const char* k : {"pus", "cores"}) big["context"][k] = 16;
    big["context"]["cpu_model"] = "Bigger CPU";
    for (auto& r : big["results"])
        if (r["threads"] == 2) r["threads"] = 16;
    save(big, dir.file("big.json"));
    Outcome r = run_suite({"compare", fixture("vm-native.json"), dir.file("big.json")});
    ASSERT_EQ(r.status, 0) << describe(r);
    EXPECT_NE(r.out.find("add random 64MiB t=2 compact/local (all threads: 2 | 16)"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("126 point(s) of [1] found"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("cpu_model  machine"), std::string::npos) << r.out;
    // The one-thread points match as before; a copy of the same figures is 1, with an interval
    // from resampling each file's repetitions around it.
    const auto row = r.out.find("copy sequential 16KiB t=1 compact/local ");
    ASSERT_NE(row, std::string::npos) << r.out;
    const std::string line = r.out.substr(row, r.out.find('\n', row) - row);
    EXPECT_NE(line.find("1.000x ["), std::string::npos) << line;
    // Another machine and another build at once: which made the difference? Refused.
    big["context"]["compiler_flags"] = "-O2";
    save(big, dir.file("big-o2.json"));
    expect_one_line_error(run_suite({"compare", fixture("vm-native.json"), dir.file("big-o2.json")}),
                          "differ both as machines (cpu_model, cores, pus)");
    EXPECT_EQ(run_suite({"compare", fixture("vm-native.json"), dir.file("big-o2.json"), "--force"}).status, 0);
}
