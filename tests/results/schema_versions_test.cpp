// Files of both result schema versions read alike: a committed schema-1 file
// (tests/fixtures/results/v1-mpm-case-index.json, its --case stored as an index) reads with the
// case's name, through the order version 1 froze, and so meets the same point of a schema-2 file,
// which stores the name. The frozen order itself is checked here, so that it cannot drift.
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "harness/kernel/kernel.hpp"
#include "harness/results/history.hpp"
#include "harness/results/result_file.hpp"
#include "harness/results/sqlite_db.hpp"
#include "tests/results/result_fixtures.hpp"

namespace {

using nlohmann::json;
using namespace suite;
using namespace suite::test;

const std::string v1_file = "v1-mpm-case-index.json";

TEST(ResultSchema, Version1OrderOfTheMpmCasesIsFrozen) {
    for (const char* name : {"mpm-p2g", "mpm-g2p", "mpm-step", "mpm-implicit-step"}) {
        const KernelEntry* k = find_kernel(name);
        ASSERT_NE(k, nullptr) << name;
        bool found = false;
        for (const auto& p : k->info.params)
            if (p.name == "case") {
                found = true;
                EXPECT_EQ(p.v1_order, (std::vector<std::string>{"dam-collapse", "dam-break", "column"})) << name;
                EXPECT_EQ(p.choices.front(), "dam-collapse") << name << ": the default case";
            }
        EXPECT_TRUE(found) << name << " has no --case";
    }
}

TEST(ResultSchema, Version1IndexOfANamedParameterReadsAsTheName) {
    const json doc = load(fixture(v1_file));
    ASSERT_EQ(doc.at("schema_version"), 1);
    // The fixture holds what version 1 wrote: the case as a number.
    std::vector<double> indices;
    for (const auto& r : doc.at("results")) indices.push_back(r.at("parameters").at("case").get<double>());
    ASSERT_EQ(indices, (std::vector<double>{0, 1}));

    const ResultFile f = parse_result_text(slurp(fixture(v1_file)), v1_file);
    EXPECT_EQ(f.schema_version, 1);
    ASSERT_EQ(f.points.size(), 2u);
    EXPECT_EQ(f.points[0].key.params.at("case"), ParamValue(std::string("dam-collapse")));
    EXPECT_EQ(f.points[1].key.params.at("case"), ParamValue(std::string("dam-break")));
    // A parameter that is a number stays one.
    EXPECT_EQ(f.points[1].key.params.at("ppe"), ParamValue(4.0));
    EXPECT_NE(f.points[1].key.label().find("case=dam-break"), std::string::npos) << f.points[1].key.label();

    // The same point written by version 2 (the name) is the same point.
    json v2 = doc;
    v2["schema_version"] = 2;
    v2["results"][1]["parameters"]["case"] = "dam-break";
    v2["results"][0]["parameters"]["case"] = "dam-collapse";
    const ResultFile g = parse_result_text(v2.dump(), "v2.json");
    ASSERT_EQ(g.points.size(), 2u);
    EXPECT_EQ(g.points[0].key, f.points[0].key);
    EXPECT_EQ(g.points[1].key, f.points[1].key);

    // Version 1 had no names: a name in a version-1 file is refused.
    json bad = doc;
    bad["results"][1]["parameters"]["case"] = "dam-break";
    EXPECT_THROW(parse_result_text(bad.dump(), "bad-v1.json"), InputError);
}

TEST(ResultSchema, HistoryPutsBothVersionsOfAPointOnOneSeries) {
    TempDir dir;
    ASSERT_TRUE(dir.ok());
    json doc = load(fixture(v1_file));
    const ResultFile v1 = parse_result_text(doc.dump(), v1_file);
    doc["schema_version"] = 2;
    doc["results"][0]["parameters"]["case"] = "dam-collapse";
    doc["results"][1]["parameters"]["case"] = "dam-break";
    doc["context"]["date"] = "2030-01-01T00:00:00";
    const ResultFile v2 = parse_result_text(doc.dump(), "v2.json");
    {
        History h = History::open_for_adding(dir.file("h.db"));
        h.add({v1}, "aaaaaaaaaaaa", "main");
        h.add({v2}, "bbbbbbbbbbbb", "main");
    }
    // The first run's rows as a build before schema 2 stored them: the case as its index.
    SqlDatabase::open(dir.file("h.db"), {true, false, 1000})
        .exec(
            "UPDATE records SET params = replace(replace(params, '\"dam-collapse\"', '0'), '\"dam-break\"', '1') "
            "WHERE run_id = (SELECT MIN(id) FROM runs)");
    const History h = History::open_for_reading(dir.file("h.db"));
    std::size_t checked = 0;
    for (const auto& s : h.series({"mpm-step", {}, ""})) {
        ASSERT_TRUE(std::holds_alternative<std::string>(s.key.params.at("case"))) << s.key.label();
        EXPECT_EQ(s.entries.size(), 2u) << s.key.label() << " " << s.figure << ": one entry a version";
        ++checked;
    }
    EXPECT_GT(checked, 0u);
}

TEST(ResultSchema, Version1FixtureIsValidAgainstVersion1Schema) {
    Outcome v = validate_against_schema(fixture(v1_file));
    EXPECT_EQ(v.status, 0) << describe(v);
    // ... and not against version 2's, whose schema_version is 2.
    Outcome strict = run_program({SUITE_PYTHON, validator_path, schema_dir + "/v2.json", fixture(v1_file)}, 60);
    EXPECT_EQ(strict.status, 1) << describe(strict);
}

}  // namespace
