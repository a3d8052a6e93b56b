// The window gate (harness/results/history_gate.hpp): a run against the last N runs of its own
// machine, build and points, pooled, and judged by check's own rule. A/A data passes; a run 30 %
// slower regresses; the run's own commit and runs outside the window are left out; a window of
// too few unstable runs is inconclusive, of enough is gated. Then the same through `suite history check` (exit 0 / 1).
#include <gtest/gtest.h>

#include <map>

#include "harness/results/check.hpp"
#include "harness/results/history_gate.hpp"
#include "tests/process.hpp"
#include "tests/results/history_fixtures.hpp"

using namespace suite;
using namespace suite::test;
using nlohmann::json;

namespace {

// Run i of a steady history: 3 points, 1 % noise between runs and repetitions, times x `level`.
json steady_run(std::size_t i, Gauss& g, double level = 1.0) {
    json doc = fixture_run(3);
    stamp(doc, i);
    for (auto& r : doc["results"]) set_times(r, noisy_times(r, level * (1 + 0.01 * g()), 0.01, g));
    return doc;
}

ResultFile as_file(const json& doc, const std::string& name) { return parse_result_text(doc.dump(), name); }

struct GateFixture {
    TempDir tmp;
    std::string db = tmp.file("h.sqlite");
    Gauss g{99};

    // `n` runs at `level`, starting at run index `first`.
    void add_runs(std::size_t first, std::size_t n, double level = 1.0, bool unstable = false) {
        History h = History::open_for_adding(db);
        for (std::size_t i = first; i < first + n; ++i) {
            json doc = steady_run(i, g, level);
            if (unstable)
                for (auto& r : doc["results"])
                    r["stability"] = {{"unstable", true}, {"reasons", {"the machine was busy"}}};
            h.add({as_file(doc, "run.json")}, "", "main");
        }
    }
    CheckReport gate(const ResultFile& run, std::size_t window, WindowBaseline* out = nullptr) {
        const History h = History::open_for_reading(db);
        const RunIdentity id = identify_run(run);
        SeriesFilter f;
        f.fingerprints = {id.fingerprint};
        f.context_class = id.context_class;
        WindowBaseline base = window_baseline(h.series(f), run, id, h.find_run(run_content_hash(run)), window, db);
        EXPECT_FALSE(base.file.points.empty());
        CheckReport rep = check_run(base.file, run, GateRule{}, true);
        if (out) *out = std::move(base);
        return rep;
    }
};

}  // namespace

TEST(HistoryGate, AnotherRunOfTheSameBuildDoesNotRegress) {
    GateFixture f;
    f.add_runs(0, 12);
    WindowBaseline base;
    const CheckReport rep = f.gate(as_file(steady_run(20, f.g), "aa.json"), 10, &base);
    EXPECT_EQ(base.runs_pooled, 10u) << "the last 10 of 12";
    ASSERT_EQ(base.file.points.size(), 3u);
    EXPECT_EQ(base.file.points[0].measures.at(0).samples.size(), 50u) << "10 runs x 5 repetitions pooled";
    EXPECT_EQ(rep.points_compared, 3u);
    EXPECT_EQ(rep.count(Verdict::regressed), 0u) << render_check_text(rep);
    EXPECT_EQ(rep.count(Verdict::improved), 0u) << render_check_text(rep);
}

TEST(HistoryGate, ARunThirtyPercentSlowerRegresses) {
    GateFixture f;
    f.add_runs(0, 10);
    const CheckReport rep = f.gate(as_file(steady_run(20, f.g, 1.3), "slow.json"), 10);
    EXPECT_EQ(rep.count(Verdict::regressed), 3u) << render_check_text(rep);
    for (const auto& x : rep.findings) EXPECT_NEAR(x.run / x.baseline, 1 / 1.3, 0.03);
}

TEST(HistoryGate, TheRunsOwnCommitAndRunsBeforeTheWindowAreLeftOut) {
    GateFixture f;
    f.add_runs(0, 10, 1.3);  // old and slow
    f.add_runs(10, 5);       // recent and fast
    json run = steady_run(30, f.g);
    run["context"]["git_revision"] = made_up_commit(14);  // a rebuild of the latest commit
    WindowBaseline base;
    const CheckReport rep = f.gate(as_file(run, "run.json"), 4, &base);
    EXPECT_EQ(base.runs_pooled, 4u) << "runs 10..13: commit 14 is the run's own";
    EXPECT_EQ(rep.count(Verdict::regressed) + rep.count(Verdict::improved), 0u) << render_check_text(rep);
    // Once added itself, the run is not its own baseline either.
    History::open_for_adding(f.db).add({as_file(run, "run.json")}, "", "main");
    EXPECT_EQ(f.gate(as_file(run, "run.json"), 4).count(Verdict::regressed), 0u);
}

TEST(HistoryGate, AWindowOfTooFewUnstableRunsIsInconclusiveAndOfEnoughIsGated) {
    GateFixture f;
    f.add_runs(0, 4, 1.0, true);
    const ResultFile slow = as_file(steady_run(20, f.g, 1.3), "slow.json");
    const CheckReport rep = f.gate(slow, 10);
    EXPECT_EQ(rep.count(Verdict::regressed), 0u) << render_check_text(rep);
    EXPECT_EQ(rep.count(Verdict::inconclusive), 3u) << render_check_text(rep);
    // Six flagged runs and no stable one: the window is the six, and the band they make gates
    // the point (a DRAM point whose 5 repetitions always spread would otherwise never be gated).
    f.add_runs(4, 2, 1.0, true);
    WindowBaseline base;
    f.gate(slow, 10, &base);
    ASSERT_EQ(base.file.points.size(), 3u);
    EXPECT_FALSE(base.file.points.front().unstable);
    HistoryRule rule;
    parse_history_tolerance("auto", rule);
    const CheckReport banded = gate_with_bands(base, slow, rule);
    EXPECT_EQ(banded.count(Verdict::regressed), 3u) << render_check_text(banded);
}

TEST(HistoryGate, ATaskClockIsWidenedByItsPointsRepetitionsAsTheRateIs) {
    // The task-clock a unit of work is the repetitions' time read again: where a run's spread
    // repetitions leave its bandwidth inconclusive, its task-clock must not regress alone.
    auto with_task_clock = [](json doc) {
        for (auto& r : doc["results"]) {
            const double t = r["time_s"]["median"].get<double>() * 1e6;
            r["counters"] = {{"available", true},
                             {"events",
                              {{{"name", "task-clock"},
                                {"available", true},
                                {"per_element", t},
                                {"per_call", {{"min", t * 1e6}, {"median", t * 1e6}, {"max", t * 1e6}}}}}}};
        }
        return doc;
    };
    GateFixture f;
    {
        History h = History::open_for_adding(f.db);
        for (std::size_t i = 0; i < 6; ++i)
            h.add({as_file(with_task_clock(steady_run(i, f.g)), "run.json")}, "", "main");
    }
    HistoryRule rule;
    parse_history_tolerance("auto", rule);
    auto verdicts = [&](double level, double spread) {
        json doc = with_task_clock(fixture_run(3));
        stamp(doc, 20);
        for (auto& r : doc["results"]) set_times(r, noisy_times(r, level, spread, f.g));
        doc = with_task_clock(doc);
        const ResultFile run = as_file(doc, "run.json");
        WindowBaseline base;
        f.gate(run, 10, &base);
        std::map<std::string, std::vector<Verdict>> out;
        for (const Finding& x : gate_with_bands(base, run, rule).findings) out[x.figure].push_back(x.verdict);
        return out;
    };
    // 30 % slower, repetitions 1 % apart: both figures regress at every point.
    auto tight = verdicts(1.3, 0.01);
    EXPECT_EQ(tight["bandwidth GB/s"], std::vector<Verdict>(3, Verdict::regressed));
    EXPECT_EQ(tight["counter task-clock per element"], std::vector<Verdict>(3, Verdict::regressed));
    // As slow, repetitions 30 % apart: the bandwidth is inconclusive, and so is the task-clock.
    auto wide = verdicts(1.3, 0.3);
    EXPECT_EQ(wide["bandwidth GB/s"], std::vector<Verdict>(3, Verdict::inconclusive));
    EXPECT_EQ(wide["counter task-clock per element"], std::vector<Verdict>(3, Verdict::inconclusive));
}

TEST(HistoryGate, PoolingConcatenatesRepetitionsAndTakesTheirMedian) {
    SeriesEntry a, b;
    a.median = 10;
    a.samples = {9, 10, 11};
    b.median = 20;
    b.samples = {19, 20, 21, 22};
    Measure like;
    like.name = "bandwidth";
    like.unit = "GB/s";
    const Measure m = pool_entries({&a, &b}, like);
    EXPECT_EQ(m.samples.size(), 7u);
    EXPECT_DOUBLE_EQ(m.median, 19);
    EXPECT_EQ(m.name, "bandwidth");
    // Without repetitions (a counter): the median of the runs' medians.
    a.samples.clear();
    b.samples.clear();
    SeriesEntry c = a;
    c.median = 12;
    EXPECT_DOUBLE_EQ(pool_entries({&a, &b, &c}, like).median, 12);
}

TEST(HistoryGateCli, ExitZeroForTheSameBuildAndOneForASlowerRun) {
    GateFixture f;
    f.add_runs(0, 10);
    const std::string same = f.tmp.file("same.json"), slow = f.tmp.file("slow.json");
    save_json(steady_run(20, f.g), same);
    save_json(steady_run(21, f.g, 1.3), slow);
    Outcome ok = run_suite({"history", "check", same, "--db", f.db});
    EXPECT_EQ(ok.status, 0) << describe(ok);
    EXPECT_NE(ok.out.find("10 run(s) of the history pooled"), std::string::npos) << ok.out;
    EXPECT_NE(ok.out.find("3 point(s) compared"), std::string::npos) << ok.out;
    Outcome bad = run_suite({"history", "check", slow, "--db", f.db, "--window=5"});
    EXPECT_EQ(bad.status, 1) << describe(bad);
    EXPECT_NE(bad.out.find("REGRESSED"), std::string::npos) << bad.out;
    EXPECT_NE(bad.out.find("5 run(s) of the history pooled"), std::string::npos) << bad.out;
    // A machine the history has never seen: nothing to gate against, exit 2.
    json other = steady_run(22, f.g);
    other["context"]["host"] = "elsewhere";
    save_json(other, f.tmp.file("other.json"));
    Outcome none = run_suite({"history", "check", f.tmp.file("other.json"), "--db", f.db});
    EXPECT_EQ(none.status, 2) << describe(none);
    EXPECT_NE(none.err.find("no run of this machine"), std::string::npos) << none.err;
}
