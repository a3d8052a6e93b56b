// The history page as text: what write_dashboard puts in DIR/index.html (every series' label,
// every step's commit, the data as JSON that parses back, nothing that can close its script
// element, each series' runs' band as history check fits it, or why it has none), an empty
// history, and the refusals. That a browser draws it is the browser test's
// (tests/dashboard_browser_test.py); here a stand-in file plays Chart.js.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>

#include "harness/common/units.hpp"
#include "harness/results/dashboard.hpp"
#include "tests/process.hpp"
#include "tests/results/history_fixtures.hpp"
#include "tests/results/synthetic_series.hpp"

using namespace suite;
using namespace suite::test;
using nlohmann::json;

namespace {

const std::string data_open = "<script type=\"application/json\" id=\"history-data\">";

// Options whose chart library is a small stand-in file inside `dir`.
DashboardOptions stand_in_library(const TempDir& dir) {
    DashboardOptions o;
    o.title = "nightly & <weekly> runs";
    o.chart_js = dir.file("chart-stand-in.js");
    std::ofstream(o.chart_js) << "/* Chart.js stand-in */\n";
    return o;
}

// The embedded data, parsed back.
json embedded_data(const std::string& page) {
    const auto begin = page.find(data_open);
    if (begin == std::string::npos) throw std::runtime_error("no data block in the page");
    const auto from = begin + data_open.size();
    const auto end = page.find("</script>", from);
    return json::parse(page.substr(from, end - from));
}

// A steady series of `runs` made-up runs (history_fixtures.hpp's commits, a seeded 1 % noise
// between runs) on machine `fingerprint`; the runs listed in `unstable` are flagged, and their
// medians three times the level, far outside any band fitted from the others.
// Runs 1 % apart at 12.4 GB/s; the `unstable` ones flagged and `unstable_factor` times that (3:
// a window that wrongly held one would show it).
Series steady_band_series(const std::string& fingerprint, const std::string& kernel, std::size_t runs,
                          std::vector<std::size_t> unstable, std::uint64_t seed, double unstable_factor = 3) {
    Series s;
    s.machine = "vm-" + fingerprint + " (made up, 4 cores)";
    s.fingerprint = fingerprint;
    s.context_class = "THP madvise, -O3 -march=native";
    s.key = synthetic_key(kernel, "sequential", 1ULL << 30, 1);
    s.figure = "bandwidth";
    s.unit = "GB/s";
    Gauss g(seed);
    for (std::size_t i = 0; i < runs; ++i) {
        SeriesEntry e;
        e.commit = made_up_commit(i);
        e.branch = "main";
        e.date = "2026-01-01T00:00:00Z";
        e.run_id = static_cast<std::int64_t>(i + 1);
        e.unstable = std::find(unstable.begin(), unstable.end(), i) != unstable.end();
        e.median = 12.4 * (1 + 0.01 * g()) * (e.unstable ? unstable_factor : 1);
        e.noise = 0.01;
        s.entries.push_back(e);
    }
    return s;
}

std::size_t count(const std::string& text, const std::string& what) {
    std::size_t n = 0;
    for (auto at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
    return n;
}

}  // namespace

TEST(Dashboard, PageNamesEverySeriesAndStepAndCopiesTheLibrary) {
    TempDir tmp;
    const auto options = stand_in_library(tmp);
    const auto history = synthetic_history();
    const std::string out = tmp.file("page");
    EXPECT_EQ(write_dashboard(history, out + "/", options), out + "/index.html");
    const std::string page = slurp(out + "/index.html");
    EXPECT_EQ(slurp(out + "/chart.min.js"), "/* Chart.js stand-in */\n");
    for (const auto& s : history) {
        EXPECT_NE(page.find(s.key.label()), std::string::npos) << s.key.label();
        for (const auto& st : s.steps) EXPECT_NE(page.find(st.commit), std::string::npos) << st.commit;
    }
    // The title is text, never markup; the library is loaded from beside the page, nothing from elsewhere.
    EXPECT_NE(page.find("<title>nightly &amp; &lt;weekly&gt; runs</title>"), std::string::npos);
    EXPECT_NE(page.find("<script src=\"chart.min.js\"></script>"), std::string::npos);
    EXPECT_EQ(page.find("http://"), std::string::npos);
    EXPECT_EQ(page.find("https://"), std::string::npos);
    EXPECT_NE(page.find("5 series on 2 machines, 120 runs of 24 commits, 4 steps (2 worse)"), std::string::npos)
        << page.substr(0, 4000);
    // The lock is released: nothing but the two files is left.
    EXPECT_FALSE(std::filesystem::exists(out + "/.suite.lock"));
}

TEST(Dashboard, EmbeddedDataParsesBackWithEveryEntryAndStep) {
    TempDir tmp;
    const auto history = synthetic_history();
    const json data = embedded_data(slurp(write_dashboard(history, tmp.file("page"), stand_in_library(tmp))));
    EXPECT_EQ(data["title"], "nightly & <weekly> runs");
    ASSERT_EQ(data["series"].size(), history.size());
    for (std::size_t i = 0; i < history.size(); ++i) {
        const Series& s = history[i];
        const json& j = data["series"][i];
        EXPECT_EQ(j["label"], s.key.label());
        EXPECT_EQ(j["kernel"], s.key.kernel);
        EXPECT_EQ(j["machine"], s.machine);
        EXPECT_EQ(j["fingerprint"], s.fingerprint);
        EXPECT_EQ(j["context"], s.context_class);
        EXPECT_EQ(j["unit"], s.unit);
        EXPECT_EQ(j["direction"], s.direction == Direction::higher_is_better ? "higher" : "lower");
        ASSERT_EQ(j["entries"].size(), s.entries.size());
        for (std::size_t k = 0; k < s.entries.size(); ++k) {
            const SeriesEntry& e = s.entries[k];
            const json& je = j["entries"][k];
            EXPECT_EQ(je["commit"], e.commit);
            EXPECT_EQ(je["branch"], e.branch);
            EXPECT_EQ(je["date"], e.date);
            EXPECT_EQ(je["run_id"], e.run_id);
            EXPECT_DOUBLE_EQ(je["median"].get<double>(), e.median);
            EXPECT_DOUBLE_EQ(je["noise"].get<double>(), e.noise);
            EXPECT_EQ(je["samples"], e.samples.size());
            EXPECT_EQ(je["unstable"], e.unstable);
        }
        ASSERT_EQ(j["steps"].size(), s.steps.size());
        for (std::size_t k = 0; k < s.steps.size(); ++k) {
            EXPECT_EQ(j["steps"][k]["index"], s.steps[k].index);
            EXPECT_EQ(j["steps"][k]["commit"], s.steps[k].commit);
            EXPECT_DOUBLE_EQ(j["steps"][k]["change"].get<double>(), s.steps[k].change);
            EXPECT_EQ(j["steps"][k]["worse"], s.steps[k].worse);
        }
    }
}

TEST(Dashboard, ALabelCannotCloseTheScriptElement) {
    TempDir tmp;
    auto history = synthetic_history();
    history[0].key.access = "random</script><script>alert(1)</script>";
    const std::string page = slurp(write_dashboard(history, tmp.file("page"), stand_in_library(tmp)));
    // Only the page's own three script elements end: the data's, Chart.js's and the page's script.
    EXPECT_EQ(count(page, "</script>"), 3u);
    EXPECT_EQ(count(page, "<!--"), 0u) << "the synthetic context's comment opener must be escaped";
    const json data = embedded_data(page);
    EXPECT_EQ(data["series"][0]["label"], history[0].key.label());
    EXPECT_EQ(data["series"][4]["context"], hostile_context);
}

TEST(Dashboard, AnEmptyHistoryIsAPageThatSaysSo) {
    TempDir tmp;
    const std::string page = slurp(write_dashboard({}, tmp.file("page"), stand_in_library(tmp)));
    EXPECT_NE(page.find("The history is empty"), std::string::npos) << page;
    EXPECT_EQ(page.find("chart.min.js"), std::string::npos) << "nothing to draw, no library to load";
    EXPECT_TRUE(embedded_data(page)["series"].empty());
    EXPECT_TRUE(std::filesystem::exists(tmp.file("page/chart.min.js")));
}

TEST(Dashboard, MissingChartLibraryIsOneLineNamingThePackageAndWritesNothing) {
    TempDir tmp;
    DashboardOptions o;
    o.chart_js = tmp.file("no-such/chart.min.js");
    try {
        write_dashboard(synthetic_history(), tmp.file("page"), o);
        FAIL() << "no error without Chart.js";
    } catch (const UsageError& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("libjs-chart.js"), std::string::npos) << what;
        EXPECT_NE(what.find(o.chart_js), std::string::npos) << what;
        EXPECT_EQ(what.find('\n'), std::string::npos) << what;
    }
    EXPECT_TRUE(tmp.entries().empty()) << "nothing written, not even the directory";
}

TEST(Dashboard, AnOutputThatIsAFileIsRefusedAndLeftAsItWas) {
    TempDir tmp;
    const auto options = stand_in_library(tmp);
    const std::string file = tmp.file("taken");
    std::ofstream(file) << "keep me";
    EXPECT_THROW(write_dashboard(synthetic_history(), file, options), UsageError);
    EXPECT_EQ(slurp(file), "keep me");
}

TEST(Dashboard, TheDefaultLibraryPathIsDebians) {
    EXPECT_EQ(DashboardOptions{}.chart_js, "/usr/share/javascript/chart.js/chart.min.js");
}

TEST(Dashboard, ASeriesOfFiveRunsOrMoreShowsTheGatesBandOfItsLastStableRuns) {
    TempDir tmp;
    auto options = stand_in_library(tmp);
    options.window = 7;
    // Two series of one machine and build (so each at 2 · 0.01 / 2, the gate's Bonferroni rule);
    // the first has an unstable run inside its last seven, which the window passes over.
    const std::vector<Series> history = {steady_band_series("f1", "triad", 16, {13}, 7),
                                         steady_band_series("f1", "add", 16, {}, 8)};
    const json data = embedded_data(slurp(write_dashboard(history, tmp.file("page"), options)));
    EXPECT_EQ(data["window"], 7);
    const json& band = data["series"][0]["band"];
    ASSERT_TRUE(band.is_object()) << data["series"][0].dump();
    EXPECT_EQ(band["runs"], 7);
    EXPECT_EQ(band["first"], 8) << "runs 15, 14, 12, 11, 10, 9, 8: run 13 is unstable";
    EXPECT_DOUBLE_EQ(band["alpha"].get<double>(), 0.01);
    std::vector<double> window;
    for (std::size_t i = 8; i < 16; ++i)
        if (i != 13) window.push_back(history[0].entries[i].median);
    std::vector<double> sorted = window;
    std::sort(sorted.begin(), sorted.end());
    const double centre = band["centre"].get<double>(), low = band["low"].get<double>(),
                 high = band["high"].get<double>();
    EXPECT_NEAR(centre, sorted[3], 1e-12 * sorted[3]) << "the centre is the median of the window's medians";
    for (double m : window) {
        EXPECT_LT(low, m);
        EXPECT_GT(high, m);
    }
    EXPECT_GT(band["spread"].get<double>(), 0.002);
    EXPECT_LT(band["spread"].get<double>(), 0.03) << "a 1 % noise between runs";
    EXPECT_GT(history[0].entries[13].median, high) << "the unstable run would lie far outside: it was left out";
    EXPECT_FALSE(data["series"][0].contains("band_reason"));
    EXPECT_TRUE(data["series"][1]["band"].is_object());

    // The synthetic history: 24 runs a series, run 9 unstable, so every window is runs 14 to 23;
    // machine A's three series share 2 · alpha, machine B's two differ in context and do not.
    const json synthetic =
        embedded_data(slurp(write_dashboard(synthetic_history(), tmp.file("synthetic"), stand_in_library(tmp))));
    EXPECT_EQ(synthetic["window"], 10);
    const double alphas[] = {0.02 / 3, 0.02 / 3, 0.02 / 3, 0.02, 0.02};
    for (std::size_t i = 0; i < 5; ++i) {
        const json& b = synthetic["series"][i]["band"];
        ASSERT_TRUE(b.is_object()) << i;
        EXPECT_EQ(b["runs"], 10) << i;
        EXPECT_EQ(b["first"], 14) << i;
        EXPECT_DOUBLE_EQ(b["alpha"].get<double>(), alphas[i]) << i;
        EXPECT_LT(b["low"].get<double>(), b["centre"].get<double>()) << i;
        EXPECT_GT(b["high"].get<double>(), b["centre"].get<double>()) << i;
    }
}

TEST(Dashboard, ASeriesOfFourRunsHasNoBandAndSaysHowManyMoreItNeeds) {
    TempDir tmp;
    EXPECT_EQ(DashboardOptions{}.window, 10u);
    EXPECT_DOUBLE_EQ(DashboardOptions{}.alpha, 0.01);
    // Four runs: no band. Six of which two are flagged unstable (at the level of the others), four
    // stable: too few stable runs, so the window is all six, as history check takes it, and there
    // is a band. (Were the two three times the others, they would be the machine's jumps, and the
    // band too wide to draw.)
    const std::vector<Series> history = {steady_band_series("f1", "triad", 4, {}, 11),
                                         steady_band_series("f2", "add", 6, {1, 4}, 12, 1.0)};
    const std::string page = slurp(write_dashboard(history, tmp.file("page"), stand_in_library(tmp)));
    const json data = embedded_data(page);
    EXPECT_TRUE(data["series"][0]["band"].is_null()) << data["series"][0].dump();
    EXPECT_EQ(data["series"][0]["band_reason"], "fewer than 5 runs in the window (4): 1 more run(s) needed for a band");
    ASSERT_TRUE(data["series"][1]["band"].is_object()) << data["series"][1].dump();
    EXPECT_EQ(data["series"][1]["band"]["runs"], 6);
    EXPECT_EQ(data["series"][1]["band"]["first"], 0);
    // The legend tells the two bands apart.
    EXPECT_NE(page.find("repetitions' spread"), std::string::npos);
    EXPECT_NE(page.find("runs' band"), std::string::npos);
}

TEST(Dashboard, ZeroCountersAreListedOnceAndABandTooWideToGateIsNotDrawn) {
    TempDir tmp;
    Series zero = steady_band_series("f1", "triad", 8, {}, 21);
    zero.figure = "counter major-faults";
    zero.unit = "per call";
    for (auto& e : zero.entries) e.median = 0;
    // Medians spread from a third to three times the level: a band of more than 2x either way.
    Series wild = steady_band_series("f1", "add", 8, {}, 22);
    for (std::size_t i = 0; i < wild.entries.size(); ++i)
        wild.entries[i].median *= std::exp(1.1 * (static_cast<double>((i * 5) % 8) - 3.5) / 3.5);
    const json data = embedded_data(slurp(write_dashboard({zero, wild, steady_band_series("f1", "copy", 8, {}, 23)},
                                                          tmp.file("p"), stand_in_library(tmp))));
    ASSERT_EQ(data["series"].size(), 2u) << "the zero counter has no chart";
    ASSERT_EQ(data["all_zero"].size(), 1u);
    EXPECT_EQ(data["all_zero"][0]["figure"], "counter major-faults");
    EXPECT_TRUE(data["series"][0]["band"].is_null());
    EXPECT_NE(data["series"][0]["band_reason"].get<std::string>().find("too wide to tell a 2x change from noise"),
              std::string::npos)
        << data["series"][0].dump();
    EXPECT_TRUE(data["series"][1]["band"].is_object()) << "a steady series keeps its band";
}
