// --sort-every=auto end to end: `suite mpm` records when each reordering happened and why
// (mpm.json, front.csv's column) and ends where the natural, seeded run does; mpm-step runs a
// fixed repetition under auto and records its reorderings in the facts; a fixed K stays a number.
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tests/process.hpp"

using namespace suite::test;

namespace {

const std::string checker = std::string(SUITE_SOURCE_DIR) + "/tests/check_mpm_vtu.py";

nlohmann::json read_json(const std::string& path) { return nlohmann::json::parse(std::ifstream(path)); }

void small_run(const std::string& dir, const std::vector<std::string>& extra) {
    std::vector<std::string> args = {"mpm",      "--mesh=box:6,6,6", "--steps=40",  "--vtk-every=20",
                                     "--no-png", "--quiet",          "--out=" + dir};
    args.insert(args.end(), extra.begin(), extra.end());
    const Outcome r = run_suite(args, 120);
    ASSERT_EQ(r.status, 0) << join(args) << "\n" << describe(r);
}

}  // namespace

TEST(MpmAutoCli, MpmJsonAndFrontCsvSayWhenEachReorderingHappenedAndWhy) {
    TempDir tmp;
    const std::string a = tmp.file("natural"), c = tmp.file("every"), d = tmp.file("auto");
    small_run(a, {});
    small_run(c, {"--ordering=morton", "--particles=dynamic", "--sort-every=5", "--threads=2"});
    small_run(d, {"--ordering=hilbert", "--particles=dynamic", "--sort-threshold=0.05"});
    const nlohmann::json r = read_json(d + "/mpm.json")["reorderings"];
    EXPECT_EQ(r["schedule"], "auto");
    EXPECT_EQ(r["threshold"], 0.05);
    ASSERT_GE(r["list"].size(), 2u);
    EXPECT_EQ(r["list"][0]["cause"], "start");
    EXPECT_EQ(r["count"].get<std::size_t>(), r["list"].size());
    EXPECT_GE(r["decayed"].get<std::size_t>(), 1u);
    const std::string csv = slurp(d + "/front.csv");
    std::size_t marked = 0;
    for (std::size_t at = csv.find(",decayed,"); at != std::string::npos; at = csv.find(",decayed,", at + 1)) ++marked;
    EXPECT_EQ(marked, r["decayed"].get<std::size_t>());
    EXPECT_EQ(r["renumber_share"], 0.05) << "dynamic's default";
    EXPECT_TRUE(r["list"][0]["renumbered"].get<bool>()) << "the start renumbers the grid";
    std::size_t renumbered = 0;
    for (const auto& e : r["list"]) {
        renumbered += e["renumbered"].get<bool>() ? 1 : 0;
        if (e["cause"] == "decayed") {
            EXPECT_GE(e["decay"].get<double>(), 0.05) << e;
            EXPECT_EQ(e["renumbered"].get<bool>(), e["outside"].get<double>() >= 0.05) << e;
        }
    }
    EXPECT_EQ(r["renumbered"].get<std::size_t>(), renumbered);
    const nlohmann::json every = read_json(c + "/mpm.json")["reorderings"];
    EXPECT_EQ(every["schedule"], "every 5 steps");
    EXPECT_EQ(every["every"], 8) << "40 steps, every 5";
    EXPECT_TRUE(every["threshold"].is_null());
    EXPECT_TRUE(every["renumber_share"].is_null()) << "a fixed K renumbers at every reordering";
    EXPECT_EQ(every["renumbered"], every["count"]);
    EXPECT_TRUE(read_json(a + "/mpm.json")["reorderings"].is_null()) << "seeded particles never reorder";
    // The reorderings change the order, not the physics: the particles end where the seeded run's do.
    for (const auto& other : {c, d}) {
        const Outcome py = run_program({SUITE_PYTHON, checker, a, other}, 120);
        if (py.status == 3) GTEST_SKIP() << py.out;
        EXPECT_EQ(py.status, 0) << other << "\n" << describe(py);
    }
}

TEST(MpmAutoCli, MpmStepUnderAutoRunsAFixedRepetitionAndRecordsItsReorderings) {
    TempDir tmp;
    const std::string out = tmp.file("r.json");
    const Outcome r = run_suite({"--kernel=mpm-step", "--case=dam-break", "--warm-steps=60", "--mesh=box:6,6,6",
                                 "--particles=dynamic", "--threads=1", "--reps=3", "--quiet", "--out=" + out},
                                120);
    ASSERT_EQ(r.status, 0) << describe(r);
    const nlohmann::json rec = read_json(out)["results"].at(0);
    EXPECT_EQ(rec["parameters"]["sort-every"], "auto") << "the default, recorded by its name";
    const std::string detail = rec["verification"]["detail"];
    EXPECT_TRUE(rec["verification"]["passed"].get<bool>()) << detail;
    EXPECT_NE(detail.find("reorder"), std::string::npos) << detail;
    const nlohmann::json& f = rec["facts"];
    EXPECT_EQ(f["sort-threshold"]["value"], 1) << "dynamic's default (docs/mpm.md)";
    EXPECT_EQ(f["renumber-share"]["value"], 0.05) << "dynamic's default (docs/mpm.md)";
    EXPECT_LE(f["renumberings"]["value"].get<double>(), f["reorderings"]["value"].get<double>());
    EXPECT_EQ(f["reorderings"]["value"], f["reorderings-decayed"]["value"]) << "auto reorders only on decay";
    // A fixed K stays a number; a name that is neither is refused in one line.
    const Outcome k = run_suite({"--kernel=mpm-step", "--mesh=box:6,6,6", "--particles=sorted", "--sort-every=7",
                                 "--threads=1", "--reps=2", "--quiet", "--out=" + tmp.file("k.json")},
                                120);
    ASSERT_EQ(k.status, 0) << describe(k);
    EXPECT_EQ(read_json(tmp.file("k.json"))["results"].at(0)["parameters"]["sort-every"], 7);
    const Outcome bad = run_suite({"--kernel=mpm-step", "--sort-every=sometimes", "--dry-run"}, 60);
    EXPECT_EQ(bad.status, 2) << describe(bad);
    EXPECT_NE(bad.err.find("--sort-every=sometimes: auto or a number"), std::string::npos) << bad.err;
}
