// The Mann–Whitney test and the bootstrap interval of harness/common/stats.hpp against tables
// computed with SciPy (tests/fixtures/stats/make_tables.py writes tables.json; its header says
// how each table was made). Every case is checked, and a failure names it.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <vector>

#include "harness/common/stats.hpp"

using namespace suite;
using nlohmann::json;

namespace {

json tables() {
    const std::string path = std::string(SUITE_SOURCE_DIR) + "/tests/fixtures/stats/tables.json";
    std::ifstream in(path);
    if (!in) throw std::runtime_error("cannot read " + path);
    return json::parse(in);
}

// |got - want| within `relative` of want: p-values span 1e-30 to 1, so an absolute tolerance
// would pass a tiny p computed as 0.
::testing::AssertionResult close(double got, double want, double relative) {
    if (std::fabs(got - want) <= relative * std::fabs(want)) return ::testing::AssertionSuccess();
    return ::testing::AssertionFailure() << "got " << got << ", SciPy " << want << " (relative error "
                                         << std::fabs(got - want) / std::fabs(want) << ", allowed " << relative << ")";
}

}  // namespace

TEST(Stats, MannWhitneyMatchesTheSciPyTable) {
    const json t = tables();
    const json& cases = t.at("mann_whitney");
    ASSERT_GE(cases.size(), 30u) << "the table lost its cases";
    std::size_t exact = 0;
    for (const json& c : cases) {
        const std::string name = c.at("name").get<std::string>();
        SCOPED_TRACE(name);
        const auto x = c.at("x").get<std::vector<double>>(), y = c.at("y").get<std::vector<double>>();
        const RankTest r = mann_whitney(x, y);
        const bool want_exact = c.at("exact").get<bool>();
        exact += want_exact;
        EXPECT_EQ(r.exact, want_exact) << name << ": exact counting iff no ties and both samples <= 30";
        EXPECT_EQ(r.u, c.at("u").get<double>()) << name;
        // Exact p-values are ratios of counts: only rounding apart. The normal approximation
        // goes through erfc, whose implementations agree to about 1e-15 relative, far from 1e-9.
        const double tolerance = want_exact ? 1e-12 : 1e-9;
        EXPECT_TRUE(close(r.p_x_smaller, c.at("p_x_smaller").get<double>(), tolerance)) << name << ": p_x_smaller";
        EXPECT_TRUE(close(r.p_x_larger, c.at("p_x_larger").get<double>(), tolerance)) << name << ": p_x_larger";
    }
    // Both branches are in the table, so a change to either is seen.
    EXPECT_GE(exact, 10u);
    EXPECT_GE(cases.size() - exact, 10u);
}

// The exact bootstrap distribution is discrete; the table brackets each percentile between the
// distribution's quantiles at the level's tail -+ 6 standard deviations of a percentile's
// coverage over `resamples` draws, a bracket a correct implementation misses with the stored
// probability (below 1e-7, most far below). A wrong index, tail or level lands outside.
TEST(Stats, MedianRatioIntervalLandsInTheExactBootstrapBrackets) {
    const json t = tables();
    const json& draws = t.at("interval_draws");
    const auto resamples = draws.at("resamples").get<unsigned>();
    const auto seeds = draws.at("seeds").get<std::vector<unsigned long long>>();
    const json& cases = t.at("median_ratio_interval");
    ASSERT_GE(cases.size(), 6u) << "the table lost its cases";
    for (const json& c : cases) {
        const std::string name = c.at("name").get<std::string>();
        const auto x = c.at("x").get<std::vector<double>>(), y = c.at("y").get<std::vector<double>>();
        for (const json& l : c.at("levels")) {
            const double level = l.at("level").get<double>();
            const auto low = l.at("low").get<std::vector<double>>(), high = l.at("high").get<std::vector<double>>();
            for (unsigned long long seed : seeds) {
                SCOPED_TRACE(name + ", level " + std::to_string(level) + ", seed " + std::to_string(seed));
                const Interval r = median_ratio_interval(x, y, level, resamples, seed);
                EXPECT_EQ(r.estimate, c.at("estimate").get<double>()) << name;
                // The ratios are the same doubles divided the same way: exact comparisons.
                EXPECT_GE(r.low, low[0]) << name << ": low below the bracket [" << low[0] << ", " << low[1] << "]";
                EXPECT_LE(r.low, low[1]) << name << ": low above the bracket [" << low[0] << ", " << low[1] << "]";
                EXPECT_GE(r.high, high[0]) << name << ": high below the bracket [" << high[0] << ", " << high[1] << "]";
                EXPECT_LE(r.high, high[1]) << name << ": high above the bracket [" << high[0] << ", " << high[1] << "]";
            }
        }
    }
}
