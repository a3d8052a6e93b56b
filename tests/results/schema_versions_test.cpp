// Files of both result schema versions read alike: a committed schema-1 file
// (tests/fixtures/results/v1-mpm-case-index.json, its --case stored as an index) reads with the
// case's name, through the order version 1 froze, and so meets the same point of a schema-2 file,
// which stores the name. The frozen order itself is checked here, so that it cannot drift.
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "harness/kernel/kernel.hpp"
#include "harness/results/result_file.hpp"
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

TEST(ResultSchema, Version1FixtureIsValidAgainstVersion1Schema) {
    Outcome v = validate_against_schema(fixture(v1_file));
    EXPECT_EQ(v.status, 0) << describe(v);
    // ... and not against version 2's, whose schema_version is 2.
    Outcome strict = run_program({SUITE_PYTHON, validator_path, schema_dir + "/v2.json", fixture(v1_file)}, 60);
    EXPECT_EQ(strict.status, 1) << describe(strict);
}

}  // namespace
