// The between-run band of the history gate (harness/results/history_band.hpp) and what it is for:
// a machine whose runs move from run to run while each run's repetitions stay tight (this VM's
// memory) false-alarms under check's rule on the pooled window, however the repetitions are
// tested, and not under the band; a 1.25x slowdown of a steady point is still caught at
// --tolerance=auto. Then history check's --tolerance=auto, --base-commit and --markdown, and
// history noise, through the command line.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "harness/results/history_gate.hpp"
#include "harness/results/history_noise.hpp"
#include "tests/process.hpp"
#include "tests/results/history_fixtures.hpp"

using namespace suite;
using namespace suite::test;
using nlohmann::json;

namespace {

void expect_one_line_error(const Outcome& r, const std::string& needle) {
    EXPECT_EQ(r.status, 2) << describe(r);
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << describe(r);
    EXPECT_NE(r.err.find(needle), std::string::npos) << "stderr lacks '" << needle << "'\n" << describe(r);
}

// Run i of a history of 3 points whose first point moves `between` (a relative standard
// deviation) from run to run and the others 1 %; every run's repetitions within 0.5 %.
json drifting_run(std::size_t i, Gauss& g, double between, double slower = 1.0) {
    json doc = fixture_run(3);
    stamp(doc, i);
    bool first = true;
    for (auto& r : doc["results"]) {
        const double level = slower * (1 + (first ? between : 0.01) * g());
        set_times(r, noisy_times(r, level, 0.005, g, 7));
        first = false;
    }
    return doc;
}

ResultFile band_file(const json& doc, const std::string& name) { return parse_result_text(doc.dump(), name); }

struct BandHistory {
    TempDir tmp;
    std::string db = tmp.file("h.sqlite");
    Gauss g{2026};
    void add(std::size_t first, std::size_t n, double between, double slower = 1.0, const std::string& commit = "") {
        History h = History::open_for_adding(db);
        for (std::size_t i = first; i < first + n; ++i)
            h.add({band_file(drifting_run(i, g, between, slower), "run.json")}, commit, "main");
    }
    std::vector<Series> all() const { return History::open_for_reading(db).series(); }
};

// Qn of the logarithms, the long way: the k-th smallest pairwise distance, k = h(h - 1)/2, h = n/2 + 1.
double log_qn_raw(std::vector<double> v) {
    for (double& x : v) x = std::log(x);
    std::vector<double> d;
    for (std::size_t i = 0; i < v.size(); ++i)
        for (std::size_t j = i + 1; j < v.size(); ++j) d.push_back(std::fabs(v[i] - v[j]));
    std::sort(d.begin(), d.end());
    const std::size_t h = v.size() / 2 + 1;
    return d[h * (h - 1) / 2 - 1];
}

Measure rate(double median, std::vector<double> samples) {
    Measure m;
    m.name = "bandwidth";
    m.unit = "GB/s";
    m.direction = Direction::higher_is_better;
    m.median = m.best = median;
    m.samples = std::move(samples);
    return m;
}

}  // namespace

TEST(HistoryBand, IsTheStudentTPredictionIntervalOfTheLogMedians) {
    const std::vector<double> medians = {10.0, 10.4, 9.7, 10.1, 9.9};
    const RunBand b = fit_band(medians, {}, 0.05, 5);
    ASSERT_TRUE(b.usable());
    EXPECT_NEAR(b.centre, 10.0, 1e-12) << "the median of the medians";
    // Qn of five: the third smallest distance, 10.1/9.9, times its factor for n = 5, worth 1.968
    // degrees of freedom (bench/qn_constants.py).
    EXPECT_NEAR(log_qn_raw(medians), std::log(10.1 / 9.9), 1e-12);
    EXPECT_NEAR(b.spread, 1.6569 * std::log(10.1 / 9.9), 1e-12);
    EXPECT_EQ(b.spread, b.own_spread) << "no other series: nothing pooled";
    EXPECT_NEAR(b.df, 1.968, 1e-12);
    // t(0.975) at 1.968 degrees of freedom = 4.37040 (scipy.stats.t.ppf); sqrt(1 + 1/5) for one new run.
    EXPECT_NEAR(b.quantile, 4.37040, 1e-4);
    EXPECT_NEAR(b.half_width, b.quantile * b.spread * std::sqrt(1.2), 1e-12);
    EXPECT_NEAR(b.low * b.high, 100.0, 1e-9) << "symmetric in log units about the centre";
    // A stray run moves neither the centre nor the spread much.
    const RunBand stray = fit_band({10.0, 10.4, 9.7, 10.1, 6.0}, {}, 0.05, 5);
    EXPECT_LT(stray.spread, 0.06) << "their standard deviation is 0.23";
    // The centre from other runs (a base commit's two): the same spread, a wider band.
    const RunBand based = fit_band(medians, {10.2, 10.3}, 0.05, 5);
    EXPECT_NEAR(based.centre, std::sqrt(10.2 * 10.3), 1e-12) << "the middle of two logarithms";
    EXPECT_NEAR(based.half_width / b.half_width, std::sqrt(1.5 / 1.2), 1e-12);
    // Too few runs, or a median that is not positive: no band.
    EXPECT_FALSE(fit_band({10, 10.4, 9.7, 10.1}, {}, 0.05, 5).usable());
    EXPECT_FALSE(fit_band({10, 10.4, 9.7, 0, 10.1}, {}, 0.05, 5).usable());
    EXPECT_NEAR(fit_band({10, 10.4, 9.7, 10.1}, {}, 0.05, 5).centre, std::sqrt(10 * 10.1), 1e-12)
        << "the centre is known all the same";
}

TEST(HistoryBand, AlphaIsSharedAmongTheFiguresTheRunGates) {
    EXPECT_NEAR(band_alpha(0.01, 90), 0.02 / 90, 1e-15);
    EXPECT_DOUBLE_EQ(band_alpha(0.01, 0), 0.02) << "no figure: one";
    EXPECT_DOUBLE_EQ(band_alpha(0.6, 1), 1.0) << "never above 1";
    // More figures, a wider band for each, on one window of ten runs.
    const std::vector<double> w = {100, 97, 103, 99, 101, 96, 104, 98, 102, 100.5};
    EXPECT_GT(fit_band(w, {}, band_alpha(0.01, 90), 5).half_width, fit_band(w, {}, band_alpha(0.01, 3), 5).half_width);
}

TEST(HistoryBand, AChangeInsideTheBandIsUnchangedWhateverTheRepetitionsSay) {
    RunBand band = fit_band({100, 97, 103, 99, 101, 96, 104}, {}, 0.01, 5);
    band.typical_se = 0.005;  // the window's medians, each known to 0.5 % from its repetitions
    ASSERT_TRUE(band.usable());
    ASSERT_LT(band.low, 85.0);
    // 14 % slower than the centre, every repetition below every pooled one: check alone regresses it.
    const Measure base = rate(100, {99, 100, 101, 100, 99, 101}), run = rate(86, {86, 86.2, 85.8, 86.1, 85.9});
    HistoryRule rule;
    EXPECT_EQ(judge(base, run, rule.gate).verdict, Verdict::regressed);
    const Finding inside = judge_with_band(base, run, band, rule);
    EXPECT_EQ(inside.verdict, Verdict::unchanged);
    EXPECT_NE(inside.note.find("inside the band of the last 7 runs"), std::string::npos) << inside.note;
    EXPECT_NEAR(inside.allowed, 1 - band.low / band.centre, 1e-12) << "the band's lower edge, as a fall";
    // Outside the band, its repetitions tight: regressed.
    ASSERT_GT(band.low, 55.0);
    const Measure far = rate(50, {50, 50.1, 49.9, 50.2, 49.8});
    EXPECT_EQ(judge_with_band(base, far, band, rule).verdict, Verdict::regressed);
    // Outside the band, but its repetitions spread so that the band they widen holds it: inconclusive.
    const Measure spread = rate(50, {30, 50, 101, 102, 45});
    EXPECT_EQ(judge_with_band(base, spread, band, rule).verdict, Verdict::inconclusive);
}

TEST(HistoryBand, ARunAndItsRerunAreJudgedOnTheirMean) {
    RunBand band = fit_band({100, 97, 103, 99, 101, 96, 104}, {}, 0.01, 5);
    band.typical_se = 0.005;
    ASSERT_TRUE(band.usable());
    // For the mean of two runs whose noise correlates 0.5: sqrt(0.75 + 1/7) against sqrt(1 + 1/7).
    const RunBand pair = band.for_pair();
    EXPECT_DOUBLE_EQ(pair.run_share, (1 + rerun_correlation) / 2);
    EXPECT_NEAR(pair.half_width / band.half_width, std::sqrt((0.75 + 1.0 / 7) / (1 + 1.0 / 7)), 1e-12);
    EXPECT_NEAR(pair.low * pair.high, band.centre * band.centre, 1e-9);
    const Measure base = rate(100, {99, 100, 101, 100, 99, 101});
    HistoryRule rule;
    rule.auto_tolerance = true;
    // Both runs just inside a run's band, outside the pair's: each alone is unchanged, the two regress.
    const double d = (band.half_width + pair.half_width) / 2;
    const double slow = 100 * std::exp(-d);
    const Measure run = rate(slow, {slow, slow * 1.001, slow * 0.999, slow, slow}),
                  rerun = rate(slow * 1.002, {slow, slow * 1.003, slow * 1.002, slow * 1.001, slow * 1.002});
    ASSERT_EQ(judge_with_band(base, run, band, rule).verdict, Verdict::unchanged);
    ASSERT_EQ(judge_with_band(base, rerun, band, rule).verdict, Verdict::unchanged);
    const Finding both = judge_pair(base, run, rerun, band, rule);
    EXPECT_EQ(both.verdict, Verdict::regressed) << both.note;
    EXPECT_NEAR(both.run, std::sqrt(run.median * rerun.median), 1e-9) << "the run column shows the pair's mean";
    // One stray run, however far, with a rerun that did not move: inconclusive, both changes named.
    const Measure stray = rate(40, {40, 40.1, 39.9, 40, 40}), steady = rate(101, {101, 100.9, 101.1, 101, 101});
    ASSERT_EQ(judge_with_band(base, stray, band, rule).verdict, Verdict::regressed);
    const Finding one = judge_pair(base, stray, steady, band, rule);
    EXPECT_NE(one.verdict, Verdict::regressed);
    // The mean of 40 and 101 is 64, outside the band: it is the rerun that says no.
    EXPECT_EQ(one.verdict, Verdict::inconclusive);
    EXPECT_NE(one.note.find("run -60%, rerun +1%"), std::string::npos) << one.note;
    // Without a band, each run by check's rule, and the verdict only where both agree.
    const Measure far = rate(50, {50, 50.1, 49.9, 50.2, 49.8});
    EXPECT_EQ(judge_pair(base, far, far, RunBand{}, rule).verdict, Verdict::regressed);
    const Finding no_band = judge_pair(base, far, steady, RunBand{}, rule);
    EXPECT_EQ(no_band.verdict, Verdict::inconclusive);
    EXPECT_NE(no_band.note.find("regressed here but not in the rerun"), std::string::npos) << no_band.note;
}

TEST(HistoryBand, AutoToleranceFollowsEachSeriesSpreadWithAFloor) {
    HistoryRule rule;
    parse_history_tolerance("auto", rule);
    ASSERT_TRUE(rule.auto_tolerance);
    // A steady series (0.3 % between runs): 5 % slower is far outside its band and beyond 1 %.
    const RunBand tight = fit_band({100, 100.3, 99.6, 100.2, 99.9, 100.4, 99.7}, {}, 0.01, 5);
    const Measure base = rate(100, {99.9, 100, 100.1, 100, 100.05}), slow = rate(95, {95, 95.1, 94.9, 95.05, 94.95});
    const Finding f = judge_with_band(base, slow, tight, rule);
    EXPECT_EQ(f.verdict, Verdict::regressed) << f.note;
    EXPECT_LT(f.allowed, 0.05);
    EXPECT_GE(f.allowed, 0.01) << "never below the floor";
    // At a fixed 10 % the same 5 % is within the minimum effect.
    parse_history_tolerance("10%", rule);
    EXPECT_FALSE(rule.auto_tolerance);
    EXPECT_EQ(judge_with_band(base, slow, tight, rule).verdict, Verdict::unchanged);
    // Without a band, under auto: check's rule at the fallback tolerance, said in the note.
    parse_history_tolerance("auto", rule);
    const Finding none =
        judge_with_band(base, rate(80, {80, 80.1, 79.9, 80.05, 79.95}), fit_band({100, 101}, {}, 0.01, 5), rule);
    EXPECT_EQ(none.verdict, Verdict::unchanged) << "20 % is within the fallback's 25 %";
    EXPECT_NE(none.note.find("(2): 3 more run(s) needed for a band; check's rule at 25.0%"), std::string::npos)
        << none.note;
    EXPECT_THROW(parse_history_tolerance("automatic", rule), UsageError);
}

TEST(HistoryBand, LeaveOneOutOnADriftingMachineFalseAlarmsUnderTheOldRuleAndNotUnderTheBand) {
    BandHistory h;
    h.add(0, 20, 0.10);  // the first point moves 10 % between runs, its repetitions 0.5 %
    const std::vector<Series> series = h.all();
    HistoryRule rule;
    const NoiseReport old_rule = measure_noise(series, 10, rule, false);
    const NoiseReport band = measure_noise(series, 10, rule, true);
    parse_history_tolerance("auto", rule);
    const NoiseReport automatic = measure_noise(series, 10, rule, true);
    EXPECT_EQ(old_rule.runs_tried.size(), 20u);
    EXPECT_GE(old_rule.runs_alarmed.size(), 2u)
        << "a 10 % drift falls past 10 % in about one run in six, each confirmed by tight repetitions";
    EXPECT_EQ(band.runs_alarmed.size(), 0u);
    EXPECT_EQ(automatic.runs_alarmed.size(), 0u);
    // The drifting series' spread is measured as about 10 %; the steady ones' as about 1 %.
    ASSERT_EQ(band.series.size(), 3u);
    const PointKey drifting = band_file(drifting_run(0, h.g, 0), "x.json").points.front().key;
    for (const SeriesNoise& n : band.series) {
        const bool drifts = n.series->key == drifting;
        EXPECT_NEAR(n.band.own_spread, drifts ? 0.10 : 0.01, drifts ? 0.05 : 0.007) << n.series->key.label();
    }
}

TEST(HistoryBand, AutoCatchesASlowdownOfASteadyPointAndNotOfTheDriftingOne) {
    BandHistory h;
    h.add(0, 10, 0.06);
    WindowBaseline base;
    json slow = drifting_run(40, h.g, 0.0, 1.25);  // every point 1.25x slower
    const ResultFile run = band_file(slow, "slow.json");
    const RunIdentity id = identify_run(run);
    base = window_baseline(h.all(), run, id, 0, 10, h.db);
    HistoryRule rule;
    parse_history_tolerance("auto", rule);
    const CheckReport rep = gate_with_bands(base, run, rule);
    std::size_t steady_regressed = 0;
    for (const Finding& f : rep.findings)
        if (f.figure == "bandwidth GB/s") {
            EXPECT_TRUE(std::isfinite(f.band_low)) << "every point has 10 runs: a band";
            if (!(f.key == run.points.front().key)) steady_regressed += f.verdict == Verdict::regressed;
        }
    EXPECT_EQ(steady_regressed, 2u) << render_check_text(rep);
    EXPECT_NE(render_check_text(rep).find("runs' band"), std::string::npos);
}

TEST(HistoryBandCli, AutoNeedsRunsBaseCommitNeedsItsRunsAndTheSummaryStaysShort) {
    BandHistory h;
    h.add(0, 3, 0.01, 1.0);
    const std::string run = h.tmp.file("run.json");
    save_json(drifting_run(30, h.g, 0.01), run);
    // Three runs: no band for any point; auto says so and stops.
    Outcome few = run_suite({"history", "check", run, "--db", h.db, "--tolerance=auto"});
    EXPECT_EQ(few.status, 2) << describe(few);
    expect_one_line_error(few, "--tolerance=auto needs 5 runs of a point in the window");
    expect_one_line_error(few, "has is 3; add 2 more run(s)");
    // With a fixed tolerance the same history gates by check's rule, and says which figures.
    Outcome fixed = run_suite({"history", "check", run, "--db", h.db});
    EXPECT_EQ(fixed.status, 0) << describe(fixed);
    EXPECT_NE(fixed.out.find("runs in the window (the fewest 3: 2 more run(s) needed): no band; check's rule at 10%"),
              std::string::npos)
        << fixed.out;
    h.add(3, 5, 0.01, 1.0);
    // A base commit the history never ran, and a malformed one.
    Outcome unknown = run_suite({"history", "check", run, "--db", h.db, "--base-commit", "0123456789abcdef"});
    EXPECT_EQ(unknown.status, 2) << describe(unknown);
    expect_one_line_error(unknown, "no run of --base-commit 0123456789abcdef");
    expect_one_line_error(run_suite({"history", "check", run, "--db", h.db, "--base-commit", "main"}),
                          "give a commit's hash");
    // The base's runs, with all 40 digits of a hash whose first 12 the history stores.
    const std::string base12 = made_up_commit(4), base40 = base12 + std::string(28, '0');
    Outcome based = run_suite({"history", "check", run, "--db", h.db, "--base-commit", base40, "--tolerance=auto"});
    EXPECT_EQ(based.status, 0) << describe(based);
    EXPECT_NE(based.out.find("1 run(s) of the history pooled"), std::string::npos) << based.out;
    // Base runs of another build only: one line naming it.
    json other = drifting_run(50, h.g, 0.01);
    other["context"]["compiler_flags"] = "-O0";
    other["context"]["git_revision"] = "abcdef1234567";
    History::open_for_adding(h.db).add({band_file(other, "other.json")}, "", "main");
    expect_one_line_error(run_suite({"history", "check", run, "--db", h.db, "--base-commit", "abcdef1234567"}),
                          "are of another build");
    // The summary for a pull request: every point 40 % slower than a history that stepped to
    // faster runs, 30 lines at most.
    h.add(8, 6, 0.01, 0.7);
    const std::string slow = h.tmp.file("slow.json"), md = h.tmp.file("gate.md");
    save_json(drifting_run(60, h.g, 0.01, 1.4), slow);
    Outcome bad =
        run_suite({"history", "check", slow, "--db", h.db, "--tolerance=auto", "--markdown", md, "--window=5"});
    EXPECT_EQ(bad.status, 1) << describe(bad);
    const std::string text = slurp(md);
    std::size_t lines = 0;
    for (char c : text) lines += c == '\n';
    EXPECT_LE(lines, 30u) << text;
    EXPECT_NE(text.find("regression(s)**"), std::string::npos) << text;
    EXPECT_NE(text.find("step(s) in this machine's history:"), std::string::npos) << text;
    EXPECT_EQ(text.find("inconclusive |"), std::string::npos) << "inconclusive figures are counted, not listed";
}

TEST(HistoryBandCli, NoiseMeasuresEachSeriesAndTheFalseAlarmsOfBothRules) {
    BandHistory h;
    h.add(0, 12, 0.10);
    Outcome band = run_suite({"history", "noise", "--db", h.db, "--tolerance=auto"});
    EXPECT_EQ(band.status, 0) << describe(band);
    EXPECT_NE(band.out.find("0 of 12 run(s) called regressed somewhere"), std::string::npos) << band.out;
    EXPECT_NE(band.out.find("next run's band"), std::string::npos) << band.out;
    Outcome old = run_suite({"history", "noise", "--db", h.db, "--tolerance=5%", "--without-band"});
    EXPECT_EQ(old.status, 0) << describe(old);
    EXPECT_NE(old.out.find("(the pooled window alone at 5%)"), std::string::npos) << old.out;
    Outcome confirmed = run_suite({"history", "noise", "--db", h.db, "--tolerance=auto", "--confirm"});
    EXPECT_EQ(confirmed.status, 0) << describe(confirmed);
    EXPECT_NE(confirmed.out.find("each confirmed by the next run): 0 of 11 run(s)"), std::string::npos)
        << confirmed.out;
    expect_one_line_error(run_suite({"history", "noise", "--db", h.db, "--tolerance=auto", "--without-band"}),
                          "--tolerance=auto needs the band");
    expect_one_line_error(run_suite({"history", "noise", "--db", h.db, "--kernel", "nosuch"}), "nosuch");
}
