// The finite element kernels through the real binary: each bad input the issue names (δ, the
// tolerances, meshes the P1 problem cannot use) refused with one line, exit status 2 and
// nothing written; a CG stopped by --cg-max is a solver failure: exit status 3, a file that
// validates, and its record not verified.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <fstream>

#include "tests/process.hpp"

using namespace suite::test;

namespace {

void write_file(const std::string& path, const std::string& text) { std::ofstream(path, std::ios::binary) << text; }

const std::string circle = "--mesh=file:" + std::string(SUITE_SOURCE_DIR) + "/../shared/meshes/unit_circle.txt";

void expect_usage_error(const Outcome& r, const std::string& exact) {
    EXPECT_EQ(r.status, 2) << describe(r);
    EXPECT_TRUE(r.out.empty()) << describe(r);
    EXPECT_EQ(r.err, "suite: error: " + exact + "\n") << describe(r);
}

}  // namespace

TEST(FemCli, BadParametersAreOneLineUsageErrors) {
    TempDir dir;
    const std::string out = "--out=" + dir.file("r.json");
    expect_usage_error(run_suite({"--kernel=fem-assembly", circle, "--delta=-1", out}),
                       "--delta=-1 for fem-assembly: δ must be a finite number >= 0 (default 0.05)");
    expect_usage_error(run_suite({"--kernel=fem-eigen", circle, "--tol=1", out}),
                       "--tol=1 for fem-eigen: the tolerance must lie strictly between 0 and 1");
    expect_usage_error(run_suite({"--kernel=fem-cg", circle, "--cg-tol=0", out}),
                       "--cg-tol=0 for fem-cg: the tolerance must lie strictly between 0 and 1");
    const Outcome word = run_suite({"--kernel=fem-spmv", circle, "--delta=abc", out});
    EXPECT_EQ(word.status, 2) << describe(word);
    EXPECT_NE(word.err.find("--delta"), std::string::npos) << describe(word);
    EXPECT_EQ(std::count(word.err.begin(), word.err.end(), '\n'), 1) << describe(word);
    EXPECT_EQ(dir.entries().size(), 0u);
}

TEST(FemCli, MeshesTheProblemCannotUseAreRefused) {
    TempDir dir;
    const std::string out = "--out=" + dir.file("r.json");
    const std::string isolated = dir.file("isolated.txt"), folded = dir.file("folded.txt");
    const std::string head = " 5 vertices in the domain\n header\n 0 0 0\n 1 1 0\n 2 1 1\n 3 0 1\n 4 5 5\n";
    write_file(isolated, head + " 2 faces in the domain\n header\n 0 1 2\n 0 2 3\n");
    write_file(folded,
               " 4 vertices in the domain\n header\n 0 0 0\n 1 1 0\n 2 1 1\n 3 0 1\n 2 faces in the domain\n header\n "
               "0 1 2\n 0 3 2\n");
    expect_usage_error(run_suite({"--kernel=fem-assembly", "--mesh=file:" + isolated, out}),
                       "--mesh=file:" + isolated +
                           ": vertex 4 belongs to no triangle (an isolated vertex leaves the mass matrix singular); "
                           "remove it from the mesh");
    expect_usage_error(run_suite({"--kernel=fem-spmv", "--mesh=file:" + folded, out}),
                       "--mesh=file:" + folded +
                           ": triangle 1 is inverted (clockwise, triangle 0 the other way round); every triangle must "
                           "have the same orientation");
    const Outcome tets = run_suite({"--kernel=fem-pattern", "--mesh=box:2,2,2", out});
    EXPECT_EQ(tets.status, 2) << describe(tets);
    EXPECT_NE(tets.err.find("need a triangle mesh"), std::string::npos) << describe(tets);
    EXPECT_EQ(dir.entries().size(), 2u);  // the two mesh files, no result
}

TEST(FemCli, CgStoppedByItsLimitIsASolverFailureWithStatus3) {
    TempDir dir;
    const std::string file = dir.file("r.json");
    const Outcome r =
        run_suite({"--kernel=fem-cg", circle, "--cg-max=3", "--threads=1", "--reps=1", "--quiet", "--out=" + file});
    EXPECT_EQ(r.status, 3) << describe(r);
    EXPECT_NE(r.err.find("solver failed: "), std::string::npos) << describe(r);
    EXPECT_NE(r.err.find("did not reach --cg-tol=1e-10 within --cg-max=3 iterations"), std::string::npos)
        << describe(r);
    const Outcome valid = validate_against_schema(file);
    EXPECT_EQ(valid.status, 0) << describe(valid);
    const auto doc = nlohmann::json::parse(slurp(file));
    ASSERT_EQ(doc["results"].size(), 1u);
    EXPECT_FALSE(doc["results"][0]["verification"]["passed"].get<bool>());
    EXPECT_TRUE(doc["results"][0]["verification"]["solver_failed"].get<bool>());
}
