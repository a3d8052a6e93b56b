// Each kind of file the suite writes is checked against its own schema in results/schema/ (a
// run's result, the roofline's ceilings, a placement), whatever lies under results/: so that
// `make run` then `make test`, the README's two commands in its order, pass.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "tests/cli/roofline_size.hpp"
#include "tests/process.hpp"

using namespace suite::test;

// The JSON files under `root` that the suite wrote: its schemas and make bench-vs's comparisons
// with likwid-bench (results/bench) are not.
static std::vector<std::string> written_json_under(const std::string& root) {
    std::vector<std::string> files;
    const std::string bench = root + "/bench/";
    for (const auto& e : std::filesystem::recursive_directory_iterator(root))
        if (e.path().extension() == ".json" && e.path().parent_path().filename() != "schema" &&
            e.path().string().rfind(bench, 0) != 0)
            files.push_back(e.path());
    return files;
}

TEST(E2E, CommittedExampleResultsStillValidate) {
    // Every file under results/ (examples, baselines, and what `make run` left there: latest.json,
    // roofline.json, plots/roofline-latest.json) stays valid as the schemas evolve, each against
    // its own kind's schema, so that `make run` then `make test` passes as the README says.
    const std::vector<std::string> files = written_json_under(std::string(SUITE_SOURCE_DIR) + "/results");
    ASSERT_FALSE(files.empty());
    Outcome v = validate_by_kind(files);
    EXPECT_EQ(v.status, 0) << describe(v);
}

TEST(E2E, WhatMakeRunWritesValidatesEachFileByItsKind) {
    // make run's commands, small, into a results/ tree of their own: a run, the ceilings, the run
    // placed on them. Each kind has its schema; a run's schema would refuse the roofline files.
    TempDir dir;
    std::filesystem::create_directories(dir.file("results/plots"));
    const std::string run = dir.file("results/latest.json"), roof = dir.file("results/roofline.json"),
                      placed = dir.file("results/plots/roofline-latest.json");
    Outcome r = run_suite({"--kernel=triad", "--sizes=64KiB", "--threads=1", "--reps=2", "--quiet", "--out=" + run});
    ASSERT_EQ(r.status, 0) << describe(r);
    Outcome c = run_suite(
        {"roofline", "--threads=1", "--min-time=0.02", roofline_test_dram_size(), "--no-png", "--out=" + roof});
    ASSERT_EQ(c.status, 0) << describe(c);
    Outcome p = run_suite({"roofline", "--place=" + run, "--ceilings=" + roof, "--no-png", "--out=" + placed});
    ASSERT_EQ(p.status, 0) << describe(p);
    const std::vector<std::string> files = written_json_under(dir.file("results"));
    EXPECT_EQ(files.size(), 3u);
    Outcome v = validate_by_kind(files);
    EXPECT_EQ(v.status, 0) << describe(v);
    EXPECT_NE(validate_against_schema(roof).status, 0) << "a roofline file is not a run's result";
    // A kind no schema describes is refused, not waved through.
    { std::ofstream(dir.file("results/other.json")) << R"({"kind": "suite-unknown", "schema_version": 1})"; }
    Outcome u = validate_by_kind({dir.file("results/other.json")});
    EXPECT_EQ(u.status, 1) << describe(u);
    EXPECT_NE(u.out.find("has no schema"), std::string::npos) << u.out;
}
