// The step detector (harness/results/steps.hpp) against a reference detector written in Python
// from steps.hpp's description, with SciPy's Mann–Whitney test (tests/fixtures/stats/
// steps_reference.py; make_tables.py stores what it finds in tables.json). Series of every
// shape the rule speaks of: none, one, two and three steps, a bump, an outlier, sides too
// short, effects below min_effect, unstable and non-finite entries, ties, one commit's runs.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <vector>

#include "harness/results/steps.hpp"

using namespace suite;
using nlohmann::json;

namespace {

json steps_table() {
    const std::string path = std::string(SUITE_SOURCE_DIR) + "/tests/fixtures/stats/tables.json";
    std::ifstream in(path);
    if (!in) throw std::runtime_error("cannot read " + path);
    return json::parse(in).at("steps");
}

Series series_of(const json& t) {
    Series s;
    s.figure = "made up";
    s.direction = t.at("direction") == "lower_is_better" ? Direction::lower_is_better : Direction::higher_is_better;
    const json& medians = t.at("medians");
    for (std::size_t i = 0; i < medians.size(); ++i) {
        SeriesEntry e;
        e.commit = t.at("commits").at(i).get<std::string>();
        e.median = medians[i].is_null() ? NAN : medians[i].get<double>();  // JSON has no NaN
        s.entries.push_back(e);
    }
    for (std::size_t i : t.at("unstable").get<std::vector<std::size_t>>()) s.entries.at(i).unstable = true;
    return s;
}

StepRule rule_of(const json& r) {
    StepRule o;
    o.min_effect = r.at("min_effect").get<double>();
    o.alpha = r.at("alpha").get<double>();
    o.min_side = r.at("min_side").get<std::size_t>();
    return o;
}

::testing::AssertionResult close(double got, double want, double relative) {
    if (std::fabs(got - want) <= relative * std::fabs(want)) return ::testing::AssertionSuccess();
    return ::testing::AssertionFailure() << "got " << got << ", reference " << want;
}

}  // namespace

TEST(HistorySteps, DetectorMatchesTheReferenceTable) {
    const json table = steps_table();
    ASSERT_GE(table.size(), 10u) << "the table lost its series";
    std::size_t with_steps = 0;
    for (const json& t : table) {
        const std::string name = t.at("name").get<std::string>();
        SCOPED_TRACE(name);
        const std::vector<Step> got = detect_steps(series_of(t), rule_of(t.at("rule")));
        const json& want = t.at("steps");
        with_steps += !want.empty();
        if (got.size() != want.size()) {  // say what was found, and go on to the next series
            std::string found;
            for (const Step& st : got) found += " " + std::to_string(st.index);
            ADD_FAILURE() << name << ": " << got.size() << " steps (at" << found << "), the reference " << want.size();
            continue;
        }
        for (std::size_t k = 0; k < got.size(); ++k) {
            const json& w = want[k];
            const std::string which = name + ", step " + std::to_string(k);
            EXPECT_EQ(got[k].index, w.at("index").get<std::size_t>()) << which;
            EXPECT_EQ(got[k].commit, w.at("commit").get<std::string>()) << which;
            EXPECT_EQ(got[k].worse, w.at("worse").get<bool>()) << which;
            // Medians of the same doubles: only the mean of two middle values can round apart.
            EXPECT_TRUE(close(got[k].before, w.at("before").get<double>(), 1e-12)) << which << ": before";
            EXPECT_TRUE(close(got[k].after, w.at("after").get<double>(), 1e-12)) << which << ": after";
            EXPECT_TRUE(close(got[k].change, w.at("change").get<double>(), 1e-9)) << which << ": change";
            // Bonferroni-corrected p, exact or normal: the tolerance of the looser of the two.
            EXPECT_TRUE(close(got[k].p, w.at("p").get<double>(), 1e-9)) << which << ": p";
        }
    }
    // Series with steps and series without: a detector that finds nothing, or everything, fails.
    EXPECT_GE(with_steps, 5u);
    EXPECT_GE(table.size() - with_steps, 5u);
}
