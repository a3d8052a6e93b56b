// The real binary on meshes: sfc-build planned (--dry-run) and run for real (result validated
// against the schema), `suite traverse` and the files it writes, and every bad mesh file or
// option refused with one line, exit status 2 and nothing written.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>

#include "tests/kernels/mesh_fixtures.hpp"
#include "tests/process.hpp"

using namespace suite::test;
using nlohmann::json;
namespace fs = std::filesystem;

namespace {

const std::string shared_meshes = std::string(SUITE_SOURCE_DIR) + "/../shared/meshes";

void write(const std::string& path, const std::string& text) { std::ofstream(path, std::ios::binary) << text; }

void expect_one_line_usage_error(const Outcome& r, const std::vector<std::string>& expected) {
    EXPECT_EQ(r.status, 2) << describe(r);
    EXPECT_TRUE(r.out.empty()) << describe(r);
    EXPECT_EQ(r.err.rfind("suite: error: ", 0), 0u) << describe(r);
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << describe(r);
    for (const auto& s : expected)
        EXPECT_NE(r.err.find(s), std::string::npos) << "stderr lacks \"" << s << "\"\n" << describe(r);
}

bool python_has_matplotlib() { return run_program({SUITE_PYTHON, "-c", "import matplotlib, numpy"}, 60).status == 0; }

class BadMeshFile : public testing::TestWithParam<BadMeshCase> {};

}  // namespace

TEST(SfcBuildCli, DryRunPlansOnePointPerMeshOrderingPhaseAndThreadCount) {
    const Outcome r =
        run_suite({"--kernel=sfc-build", "--mesh=file:" + shared_meshes + "/unit_circle_fine.txt:refine=3",
                   "--ordering=morton,rcm", "--phase=keys,all", "--threads=1,2", "--dry-run"});
    ASSERT_EQ(r.status, 0) << describe(r);
    EXPECT_NE(r.out.find("8 point(s)"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("sfc-build-keys morton 1539968 threads=2 mesh=file:"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("sfc-build rcm 1539968 threads=1"), std::string::npos) << r.out;
    // Without --mesh or a size: the kernel's default meshes, a small one and a DRAM-sized one.
    const Outcome d = run_suite({"--kernel=sfc-build", "--threads=1", "--dry-run"});
    ASSERT_EQ(d.status, 0) << describe(d);
    EXPECT_NE(d.out.find("sfc-build morton 24576 threads=1 mesh=disk:refine=6"), std::string::npos) << d.out;
    EXPECT_NE(d.out.find("sfc-build morton 6291456 threads=1 mesh=disk:refine=10"), std::string::npos) << d.out;
}

TEST(SfcBuildCli, TinyRunVerifiesAndValidatesAgainstTheSchema) {
    TempDir dir;
    const std::string out = dir.file("r.json");
    const Outcome r =
        run_suite({"--kernel=sfc-build", "--mesh=box:3,3,2", "--ordering=morton,hilbert,morton-recursive,rcm",
                   "--phase=all,keys,sort,renumber", "--threads=1,2", "--reps=2", "--quiet", "--out=" + out});
    ASSERT_EQ(r.status, 0) << describe(r);
    const Outcome v = validate_against_schema(out);
    EXPECT_EQ(v.status, 0) << describe(v);
    const json doc = json::parse(slurp(out));
    ASSERT_EQ(doc["results"].size(), 32u);
    std::set<std::string> names;
    for (const auto& rec : doc["results"]) {
        EXPECT_TRUE(rec["verification"]["passed"].get<bool>()) << rec["verification"]["detail"];
        EXPECT_EQ(rec["mesh"], "box:3,3,2");
        EXPECT_EQ(rec["size"]["requested"], 108);
        EXPECT_EQ(rec["size"]["units"], 108.0);
        EXPECT_EQ(rec["unit"], "element");
        names.insert(rec["name"].get<std::string>() + "/" + rec["ordering"].get<std::string>());
    }
    EXPECT_EQ(names.size(), 16u);
    EXPECT_TRUE(names.count("sfc-build-renumber/rcm"));
    EXPECT_NE(doc["results"][0]["verification"]["detail"].get<std::string>().find("108 tetrahedra"), std::string::npos);
}

TEST(SfcBuildCli, BadOptionsAreOneLineUsageErrors) {
    TempDir dir;
    const std::string out = "--out=" + dir.file("r.json");
    expect_one_line_usage_error(run_suite({"--kernel=add", "--mesh=disk:refine=2", out}),
                                {"'add'", "does not run on a mesh", "sfc-build"});
    expect_one_line_usage_error(run_suite({"--kernel=sfc-build", "--mesh=disk:refine=2", "--size=1000", out}),
                                {"--mesh", "--size", "together"});
    expect_one_line_usage_error(run_suite({"--kernel=sfc-build", "--phase=kys", out}),
                                {"'kys'", "did you mean 'keys'?", "keys, sort, renumber"});
    expect_one_line_usage_error(run_suite({"--kernel=add", "--phase=keys", out}), {"'add'", "no phases"});
    expect_one_line_usage_error(run_suite({"--kernel=sfc-build", "--ordering=natural", out}),
                                {"'natural'", "morton, hilbert, morton-recursive, rcm"});
    expect_one_line_usage_error(run_suite({"--kernel=sfc-build", "--mesh=sphere:3", out}),
                                {"'sphere:3'", "disk:refine=K", "box:NX,NY,NZ"});
    expect_one_line_usage_error(run_suite({"--kernel=sfc-build", "--mesh=disk:refine=14", out}),
                                {"1073741823", "refine 13 times at most"});
    expect_one_line_usage_error(run_suite({"--kernel=sfc-build", "--mesh=box:4096,4096,4096", out}),
                                {"412316860416 elements", "1073741823"});
    expect_one_line_usage_error(run_suite({"--kernel=sfc-build", "--mesh=box:600,600,490", "--dry-run", out}),
                                {"1058400000 elements", "memory available", "use a smaller mesh"});
    expect_one_line_usage_error(run_suite({"--kernel=sfc-build", "--mesh=file:" + dir.file("none.msh"), out}),
                                {"none.msh", "cannot read"});
    EXPECT_EQ(dir.entries().size(), 0u);
}

TEST_P(BadMeshFile, RefusedByNameAndLineWithNothingWritten) {
    const BadMeshCase& c = GetParam();
    TempDir dir;
    const std::string path = dir.file(c.file.name);
    write(path, c.file.text);
    const std::string where = path + ":" + std::to_string(c.line) + ": ";
    expect_one_line_usage_error(run_suite({"--kernel=sfc-build", "--mesh=file:" + path, "--out=" + dir.file("r.json")}),
                                {where, c.expected});
    expect_one_line_usage_error(run_suite({"traverse", "--mesh=file:" + path + ":refine=1", "--out=" + dir.file("t")}),
                                {where, c.expected});
    EXPECT_EQ(dir.entries(), std::vector<std::string>{c.file.name});
}

INSTANTIATE_TEST_SUITE_P(Cases, BadMeshFile, testing::ValuesIn(bad_mesh_cases()),
                         [](const auto& info) { return info.param.id; });

TEST(Traverse, WritesVtuPngAndTheNumbers) {
    TempDir dir;
    const std::string out = dir.file("tr");
    const Outcome r = run_suite({"traverse", "--mesh=file:" + shared_meshes + "/unit_circle.txt",
                                 "--ordering=natural,morton,hilbert", "--threads=1,4", "--out=" + out});
    ASSERT_EQ(r.status, 0) << describe(r);
    EXPECT_NE(r.out.find("1976 triangles, 1039 vertices"), std::string::npos) << r.out;
    const json s = json::parse(slurp(out + "/summary.json"));
    ASSERT_EQ(s["orderings"].size(), 3u);
    std::map<std::string, double> shared4;
    for (const auto& o : s["orderings"]) {
        const std::string name = o["ordering"];
        ASSERT_EQ(o["threads"].size(), 2u);
        EXPECT_EQ(o["threads"][0]["shared_elements"], 0) << "one thread shares nothing";
        shared4[name] = o["threads"][1]["shared_fraction"];
        EXPECT_GT(o["bandwidth"].get<int>(), 0);
        for (int t : {1, 4}) {
            const std::string vtu = slurp(out + "/" + name + "-t" + std::to_string(t) + ".vtu");
            EXPECT_NE(vtu.find("NumberOfPoints=\"1039\" NumberOfCells=\"1976\""), std::string::npos);
            for (const char* field : {"visit", "thread", "step"})
                EXPECT_NE(vtu.find(std::string("Name=\"") + field + "\""), std::string::npos);
            // The last element belongs to the last thread, at the end of its block.
            EXPECT_NE(vtu.find(t == 1 ? "Name=\"thread\" format=\"ascii\">\n0\n" : "\n3\n</DataArray>"),
                      std::string::npos);
        }
    }
    // The file's natural order is scattered; a curve keeps each thread's elements together.
    EXPECT_GT(shared4["natural"], 0.5);
    EXPECT_LT(shared4["morton"], 0.3);
    EXPECT_LT(shared4["hilbert"], 0.3);
    EXPECT_EQ(s["shared_key_fraction"].size(), 32u);
    if (!python_has_matplotlib()) {
        EXPECT_FALSE(s["png"]["available"].get<bool>());
        GTEST_SKIP() << SUITE_PYTHON << " has no matplotlib, so no PNGs; the summary says why: " << s["png"]["reason"];
    }
    EXPECT_TRUE(s["png"]["available"].get<bool>()) << s["png"];
    for (const char* o : {"natural", "morton", "hilbert"})
        for (int t : {1, 4})
            for (int pct : {0, 20, 40, 60, 80, 100}) {
                char name[64];
                std::snprintf(name, sizeof name, "/%s-t%d-%03d.png", o, t, pct);
                EXPECT_GT(fs::file_size(out + name), 1000u) << name;
            }
}

TEST(Traverse, BadUsageWritesNothing) {
    TempDir dir;
    const std::string file = dir.file("f");
    write(file, "x");
    expect_one_line_usage_error(run_suite({"traverse", "--mesh=disk:refine=2"}), {"--out=DIR"});
    expect_one_line_usage_error(run_suite({"traverse", "--out=" + file}), {"not a directory"});
    expect_one_line_usage_error(run_suite({"traverse", "--ordering=natural,mortn", "--out=" + dir.file("t")}),
                                {"'mortn'", "did you mean 'morton'?"});
    expect_one_line_usage_error(run_suite({"traverse", "--threads=all", "--out=" + dir.file("t")}), {"--threads=all"});
    expect_one_line_usage_error(run_suite({"traverse", "--threads=2000", "--out=" + dir.file("t")}),
                                {"thread count 2000", "1 to 1024 static blocks"});
    expect_one_line_usage_error(run_suite({"traverse", "--depth=33", "--out=" + dir.file("t")}),
                                {"--depth=33", "from 1 to 32"});
    expect_one_line_usage_error(run_suite({"traverse", "--mesh=disk:refine=11", "--out=" + dir.file("t")}),
                                {"at most 4000000"});
    expect_one_line_usage_error(run_suite({"traverse", "--out=" + dir.file("no/such/t")}), {"does not exist"});
    EXPECT_EQ(dir.entries(), std::vector<std::string>{"f"});
}
