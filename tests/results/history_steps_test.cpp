// Step detection (harness/results/steps.hpp) on a made-up history that went through the database:
// 30 commits of four points with 2 % noise between runs, and one point's bandwidth 15 % lower
// from one commit on. The detector names that commit, in that series, and nothing else. Then the
// rule on hand-made series: the minimum effect, unstable runs, one commit's runs never split.
#include <gtest/gtest.h>

#include "harness/results/history.hpp"
#include "harness/results/steps.hpp"
#include "tests/process.hpp"
#include "tests/results/history_fixtures.hpp"

using namespace suite;
using namespace suite::test;
using nlohmann::json;

namespace {

constexpr std::size_t commits = 30, step_at = 17, stepped_point = 2;

// Each run: every point at its level times (1 + 2 % noise) for the run, and 0.5 % noise between
// repetitions; the stepped point's times 1/0.85 longer from commit `step_at` on.
std::vector<ResultFile> synthetic_history(std::uint64_t seed) {
    Gauss g(seed);
    std::vector<ResultFile> out;
    for (std::size_t i = 0; i < commits; ++i) {
        json doc = fixture_run(4);
        stamp(doc, i);
        for (std::size_t p = 0; p < doc["results"].size(); ++p) {
            const double run_level = (1 + 0.02 * g()) * (p == stepped_point && i >= step_at ? 1 / 0.85 : 1.0);
            set_times(doc["results"][p], noisy_times(doc["results"][p], run_level, 0.005, g));
        }
        out.push_back(parse_result_text(doc.dump(), "run" + std::to_string(i) + ".json"));
    }
    return out;
}

Series made_series(const std::vector<double>& medians, const std::vector<std::string>& commits_of = {}) {
    Series s;
    s.figure = "bandwidth";
    for (std::size_t i = 0; i < medians.size(); ++i) {
        SeriesEntry e;
        e.commit = commits_of.empty() ? made_up_commit(i) : commits_of[i];
        e.median = medians[i];
        s.entries.push_back(e);
    }
    return s;
}

std::vector<double> flat(std::size_t n, double level, double noise, std::uint64_t seed) {
    Gauss g(seed);
    std::vector<double> v;
    for (std::size_t i = 0; i < n; ++i) v.push_back(level * (1 + noise * g()));
    return v;
}

}  // namespace

TEST(HistorySteps, ThirtyCommitsOneStepNamedAtItsCommitAndNoOther) {
    TempDir tmp;
    const std::string db = tmp.file("h.sqlite");
    const auto runs = synthetic_history(2024);
    {
        History h = History::open_for_adding(db);
        for (const auto& r : runs) h.add({r}, "", "main");  // one add a CI job
    }
    const History h = History::open_for_reading(db);
    const auto series = h.series();
    ASSERT_EQ(series.size(), 4u);
    const PointKey stepped = runs[0].points[stepped_point].key;
    std::size_t found = 0;
    for (const auto& s : series) {
        ASSERT_EQ(s.entries.size(), commits) << s.key.label();
        const auto steps = detect_steps(s);
        if (!(s.key == stepped)) {
            EXPECT_TRUE(steps.empty()) << s.key.label() << ": a step at " << steps[0].commit << " in noise";
            continue;
        }
        ASSERT_EQ(steps.size(), 1u) << s.key.label();
        EXPECT_EQ(steps[0].commit, made_up_commit(step_at));
        EXPECT_EQ(steps[0].index, step_at);
        EXPECT_NEAR(steps[0].change, -0.15, 0.02);
        EXPECT_TRUE(steps[0].worse) << "bandwidth fell";
        EXPECT_LT(steps[0].p, 0.01);
        found += steps.size();
    }
    EXPECT_EQ(found, 1u);
    // Deterministic: the same history gives the same steps.
    for (const auto& s : series) {
        const auto a = detect_steps(s), b = detect_steps(s);
        ASSERT_EQ(a.size(), b.size());
        for (std::size_t k = 0; k < a.size(); ++k) EXPECT_EQ(a[k].index, b[k].index);
    }
}

TEST(HistorySteps, NoiseAloneHasNoStepsOverManySeeds) {
    for (std::uint64_t seed = 1; seed <= 50; ++seed) {
        Series s = made_series(flat(30, 10.0, 0.02, seed));
        EXPECT_TRUE(detect_steps(s).empty()) << "seed " << seed;
    }
}

TEST(HistorySteps, TwoStepsEachNamedWithTheLevelsAroundIt) {
    std::vector<double> v = flat(36, 10.0, 0.01, 7);
    for (std::size_t i = 12; i < 36; ++i) v[i] *= 1.2;
    for (std::size_t i = 24; i < 36; ++i) v[i] *= 0.75;
    Series s = made_series(v);
    s.direction = Direction::lower_is_better;  // e.g. a latency: up is worse
    const auto steps = detect_steps(s);
    ASSERT_EQ(steps.size(), 2u);
    EXPECT_EQ(steps[0].index, 12u);
    EXPECT_EQ(steps[1].index, 24u);
    EXPECT_NEAR(steps[0].change, 0.2, 0.03);
    EXPECT_TRUE(steps[0].worse);
    EXPECT_NEAR(steps[1].change, -0.25, 0.03);
    EXPECT_FALSE(steps[1].worse);
    EXPECT_NEAR(steps[0].before, 10.0, 0.2);
    EXPECT_NEAR(steps[1].after, 9.0, 0.2);
}

TEST(HistorySteps, AChangeBelowTheMinimumEffectIsNoStep) {
    std::vector<double> v = flat(30, 10.0, 0.002, 3);
    for (std::size_t i = 15; i < 30; ++i) v[i] *= 1.03;  // certain, but 3 % < 5 %
    EXPECT_TRUE(detect_steps(made_series(v)).empty());
    StepRule looser;
    looser.min_effect = 0.02;
    ASSERT_EQ(detect_steps(made_series(v), looser).size(), 1u);
}

TEST(HistorySteps, UnstableRunsAreNotTested) {
    std::vector<double> v = flat(30, 10.0, 0.01, 5);
    Series s = made_series(v);
    // Six unstable runs far off in the middle: without them there is nothing to find.
    for (std::size_t i = 12; i < 18; ++i) {
        s.entries[i].median *= 2;
        s.entries[i].unstable = true;
    }
    EXPECT_TRUE(detect_steps(s).empty());
    for (std::size_t i = 12; i < 18; ++i) s.entries[i].unstable = false;
    EXPECT_FALSE(detect_steps(s).empty()) << "the same values, stable, are steps";
}

TEST(HistorySteps, OneCommitsRunsAreNeverSplit) {
    // Two runs of each commit; the level changes between the two runs of commit 8.
    std::vector<double> v = flat(30, 10.0, 0.005, 11);
    std::vector<std::string> c;
    for (std::size_t i = 0; i < 30; ++i) c.push_back(made_up_commit(i / 2));
    for (std::size_t i = 17; i < 30; ++i) v[i] *= 1.3;
    const auto steps = detect_steps(made_series(v, c));
    ASSERT_EQ(steps.size(), 1u);
    EXPECT_EQ(steps[0].index % 2, 0u) << "a step begins at a commit's first run";
    EXPECT_TRUE(steps[0].index == 16 || steps[0].index == 18) << steps[0].index;
}
