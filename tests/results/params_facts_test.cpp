// A kernel's parameters and facts, and a solver that did not converge, through the runner and
// every writer: the JSON record ("parameters", "facts", "verification.solver_failed") validates
// against results/schema/v1.json and reads back, points with other parameters are other points
// for compare and check, CSV has a "parameters" column, the console table a facts line, and the
// gbench writer says "solver failed". The kernel is tests/kernel/test_solver_kernel.cpp.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <fstream>
#include <functional>

#include "app/suite/defaults.hpp"
#include "harness/measure/instrument_set.hpp"
#include "harness/measure/runner.hpp"
#include "harness/results/compare.hpp"
#include "harness/results/context.hpp"
#include "harness/results/report.hpp"
#include "harness/results/result_file.hpp"
#include "tests/kernel/test_solver_kernel.hpp"
#include "tests/process.hpp"

using namespace suite;
using namespace suite::test;
using nlohmann::json;

namespace {

const Topology& topology() {
    static const Topology topo = Topology::load();
    return topo;
}

Record solve(const Params& params, const std::string& variant = "jacobi") {
    RunSettings s;
    s.pin = parse_pin("compact", topology());
    s.placement = parse_placement("local", topology());
    s.reps = 2;
    Point point;
    point.kernel = find_kernel(solver_kernel);
    point.access = {"natural", 0};
    point.variant = variant;
    point.size = 1024;
    point.params = params;
    return run_point(point, s, topology());
}

std::string render(const std::vector<Record>& records, FileFormat format = FileFormat::json) {
    static const Instruments none;
    return ResultDocument{build_context(topology(), {"suite"}, none, bandwidth_convention()), records}.render(format,
                                                                                                              true);
}

void save(const std::string& path, const std::string& text) { std::ofstream(path) << text; }

}  // namespace

TEST(ParamsFacts, TheRunnerFillsDefaultsAndReadsFactsAfterVerify) {
    const Record r = solve({{"delta", 0.25}});
    EXPECT_TRUE(r.verification.passed) << r.verification.detail;
    EXPECT_FALSE(r.verification.solver_failed);
    EXPECT_EQ(r.params, (Params{{"delta", 0.25}, {"tol", 1e-8}, {"wrong", 0.0}}));
    ASSERT_EQ(r.facts.size(), 3u);
    EXPECT_EQ(r.facts[0].name, "x0");
    EXPECT_NEAR(r.facts[0].value, 1 / 1.25, 1e-7);
    EXPECT_EQ(r.facts[1].name, "iterations");
    EXPECT_GT(r.facts[1].value, 5);
    EXPECT_EQ(r.facts[2].unit, "rows");
}

TEST(ParamsFacts, ASolverThatDoesNotConvergeIsNotVerified) {
    const Record r = solve({{"delta", 1.5}});
    EXPECT_TRUE(r.verification.solver_failed);
    EXPECT_FALSE(r.verification.passed);
    EXPECT_NE(r.verification.detail.find("no convergence"), std::string::npos) << r.verification.detail;
    const json j = to_json(r);
    EXPECT_EQ(j["verification"]["solver_failed"], true);
    EXPECT_EQ(j["verification"]["passed"], false);
    EXPECT_FALSE(to_json(solve({})).at("verification").contains("solver_failed"));
    // Google Benchmark's JSON names the failure.
    const json gb = json::parse(render({r}, FileFormat::gbench));
    ASSERT_FALSE(gb["benchmarks"].empty());
    EXPECT_EQ(gb["benchmarks"][0]["error_occurred"], true);
    EXPECT_EQ(gb["benchmarks"][0]["error_message"].get<std::string>().rfind("solver failed: ", 0), 0u)
        << gb["benchmarks"][0].dump();
}

TEST(ParamsFacts, JsonValidatesAgainstTheSchemaAndReadsBack) {
    TempDir dir;
    ASSERT_TRUE(dir.ok());
    const Record a = solve({{"delta", 0.25}}), b = solve({{"delta", 0.5}}), failed = solve({{"delta", 1.5}});
    const json ja = to_json(a);
    EXPECT_EQ(ja["parameters"], (json{{"delta", 0.25}, {"tol", 1e-8}, {"wrong", 0}}));
    EXPECT_EQ(ja["facts"]["rows"], (json{{"value", 1024}, {"unit", "rows"}}));
    EXPECT_EQ(ja["facts"]["iterations"]["unit"], "");
    // A kernel without parameters or facts writes neither field.
    Record plain = a;
    plain.params.clear();
    plain.facts.clear();
    EXPECT_FALSE(to_json(plain).contains("parameters"));
    EXPECT_FALSE(to_json(plain).contains("facts"));

    const std::string good = dir.file("solve.json");
    save(good, render({a, b, failed}));
    Outcome v = validate_against_schema(good);
    EXPECT_EQ(v.status, 0) << describe(v);

    // Read back: three points, told apart by their parameters alone.
    const ResultFile f = parse_result_text(slurp(good), good);
    ASSERT_EQ(f.points.size(), 3u);
    EXPECT_TRUE(f.notes.empty()) << f.notes.front();
    EXPECT_EQ(f.points[0].key.params, a.params);
    EXPECT_EQ(f.points[1].key.params.at("delta"), ParamValue(0.5));
    EXPECT_FALSE(f.points[2].verified);
    EXPECT_NE(f.points[0].key.label().find("delta=0.25 tol=1e-08 wrong=0"), std::string::npos)
        << f.points[0].key.label();

    // Broken copies fail validation, each at its path.
    const json doc = json::parse(slurp(good));
    const std::vector<std::pair<std::function<void(json&)>, std::string>> breaks = {
        {[](json& d) { d["results"][0]["parameters"]["delta"] = "0.25"; }, "$.results[0].parameters.delta"},
        {[](json& d) { d["results"][0]["parameters"]["Delta"] = 1; }, "$.results[0].parameters"},
        {[](json& d) { d["results"][0]["facts"]["rows"].erase("unit"); }, "$.results[0].facts.rows"},
        {[](json& d) { d["results"][0]["facts"]["rows"]["value"] = "many"; }, "$.results[0].facts.rows.value"},
        {[](json& d) { d["results"][2]["verification"]["passed"] = true; }, "$.results[2].verification"},
        {[](json& d) { d["results"][0]["verification"]["solver_failed"] = false; },
         "$.results[0].verification.solver_failed"},
    };
    for (std::size_t i = 0; i < breaks.size(); ++i) {
        SCOPED_TRACE(breaks[i].second);
        json broken = doc;
        breaks[i].first(broken);
        const std::string path = dir.file("broken" + std::to_string(i) + ".json");
        save(path, broken.dump(1));
        Outcome bad = validate_against_schema(path);
        EXPECT_EQ(bad.status, 1) << describe(bad);
        EXPECT_NE(bad.combined().find(breaks[i].second), std::string::npos) << describe(bad);
    }
    // The reader refuses parameters that are not finite numbers, naming the field.
    json bad = doc;
    bad["results"][1]["parameters"]["tol"] = "small";
    try {
        parse_result_text(bad.dump(), "bad.json");
        FAIL() << "a string parameter was read";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("results[1].parameters.tol"), std::string::npos) << e.what();
    }
}

TEST(ParamsFacts, PointsWithOtherParametersAreNotCompared) {
    const ResultFile quarter = parse_result_text(render({solve({{"delta", 0.25}})}), "a.json");
    const ResultFile half = parse_result_text(render({solve({{"delta", 0.5}})}), "b.json");
    EXPECT_THROW(render_comparison({quarter, half}, false), InputError);
    const std::string same = render_comparison({quarter, quarter}, false);
    EXPECT_NE(same.find("delta=0.25"), std::string::npos) << same;
}

TEST(ParamsFacts, CsvHasAParametersColumnAndTheTableAFactsLine) {
    const Record r = solve({{"delta", 0.25}});
    const std::string csv = render({r}, FileFormat::csv);
    const std::string header = csv.substr(0, csv.find('\n'));
    EXPECT_NE(header.find(",verified,parameters"), std::string::npos) << header;
    EXPECT_NE(csv.find(",true,delta=0.25;tol=1e-08;wrong=0"), std::string::npos) << csv;
    // The same number of columns in the header and the row.
    const std::string row = csv.substr(csv.find('\n') + 1);
    EXPECT_EQ(std::count(header.begin(), header.end(), ','), std::count(row.begin(), row.end(), ','));

    const std::string table = table_row(1, 1, r);
    const auto newline = table.find('\n');
    ASSERT_NE(newline, std::string::npos);
    const std::string facts = table.substr(newline + 1);
    EXPECT_EQ(facts.rfind("        x0=0.8, iterations=", 0), 0u) << table;
    EXPECT_NE(facts.find(", rows=1024 rows\n"), std::string::npos) << table;
    Record plain = r;
    plain.facts.clear();
    const std::string plain_row = table_row(1, 1, plain);
    EXPECT_EQ(std::count(plain_row.begin(), plain_row.end(), '\n'), 1);
}
