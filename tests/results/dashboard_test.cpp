// The history page as text: what write_dashboard puts in DIR/index.html (every series' label,
// every step's commit, the data as JSON that parses back, nothing that can close its script
// element), an empty history, and the refusals. That a browser draws it is the browser test's
// (tests/dashboard_browser_test.py); here a stand-in file plays Chart.js.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <fstream>

#include "harness/common/units.hpp"
#include "harness/results/dashboard.hpp"
#include "tests/process.hpp"
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
    EXPECT_NE(page.find("5 series on 2 machines, 120 runs of 24 commits, 4 steps (2 worse)"), std::string::npos) << page.substr(0, 4000);
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
