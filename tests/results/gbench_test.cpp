// Google Benchmark interoperability: `suite --format=gbench` writes Google Benchmark's JSON
// (context, benchmarks[] with name, run_type, iterations, real_time, cpu_time, time_unit and
// the counters as keys), consistent with the suite's own record of the same run; suite-gbench
// registers every kernel and pattern under the same names and answers Google Benchmark's flags.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <cmath>
#include <set>

#include "tests/process.hpp"

using namespace suite::test;
using nlohmann::json;

namespace {

// The fields Google Benchmark's JSON reporter writes for every run, with their types.
void expect_gbench_entry(const json& b) {
    ASSERT_TRUE(b.is_object());
    for (const char* k : {"name", "run_name", "run_type", "time_unit"})
        EXPECT_TRUE(b.contains(k) && b[k].is_string()) << k << " in " << b.dump();
    for (const char* k : {"family_index", "per_family_instance_index", "repetitions", "threads", "iterations"})
        EXPECT_TRUE(b.contains(k) && b[k].is_number_integer()) << k << " in " << b.dump();
    for (const char* k : {"real_time", "cpu_time"})
        EXPECT_TRUE(b.contains(k) && b[k].is_number()) << k << " in " << b.dump();
    EXPECT_TRUE(b["run_type"] == "iteration" || b["run_type"] == "aggregate") << b.dump();
    if (b["run_type"] == "aggregate") {
        EXPECT_TRUE(b.contains("aggregate_name")) << b.dump();
    } else {
        EXPECT_TRUE(b.contains("repetition_index")) << b.dump();
    }
}

}  // namespace

TEST(GbenchFormat, ASuiteRunInGoogleBenchmarksJson) {
    TempDir dir;
    Outcome r = run_suite({"--kernel=triad,latency", "--sizes=64KiB,1MiB", "--threads=1", "--reps=4", "--format=gbench",
                           "--out=" + dir.file("gb.json")});
    ASSERT_EQ(r.status, 0) << describe(r);
    const json doc = json::parse(slurp(dir.file("gb.json")));
    ASSERT_TRUE(doc.contains("context") && doc.contains("benchmarks")) << doc.dump().substr(0, 500);
    const json& ctx = doc["context"];
    for (const char* k : {"date", "host_name", "executable", "library_build_type"})
        EXPECT_TRUE(ctx[k].is_string()) << k;
    EXPECT_GE(ctx["num_cpus"].get<int>(), 1);
    ASSERT_TRUE(ctx["caches"].is_array());
    for (const auto& c : ctx["caches"])
        for (const char* k : {"type", "level", "size", "num_sharing"}) EXPECT_TRUE(c.contains(k)) << k;
    EXPECT_NE(ctx["suite_timing"].get<std::string>().find("cpu_time is not measured"), std::string::npos);

    // 4 points x (4 repetitions + mean, median, stddev, cv).
    const json& bs = doc["benchmarks"];
    ASSERT_EQ(bs.size(), 4u * 8u);
    std::set<std::string> names;
    for (const auto& b : bs) {
        expect_gbench_entry(b);
        EXPECT_EQ(b["time_unit"], "ns");
        names.insert(b["run_name"].get<std::string>());
    }
    EXPECT_EQ(names, (std::set<std::string>{"triad/sequential/64KiB/1/real_time", "triad/sequential/1MiB/1/real_time",
                                            "latency/random/64KiB/1/real_time", "latency/random/1MiB/1/real_time"}));
    // The numbers are the run's own: the same run in suite's JSON would hold these samples.
    const json& first = bs[0];
    EXPECT_EQ(first["run_type"], "iteration");
    EXPECT_EQ(first["repetitions"], 4);
    const double t = first["real_time"].get<double>() * 1e-9;
    ASSERT_GT(t, 0);
    ASSERT_TRUE(first.contains("bytes_per_second") && first.contains("items_per_second")) << first.dump();
    // triad: 24 B per element; 64 KiB of three arrays is 2730 elements.
    const double elements = first["items_per_second"].get<double>() * t;
    EXPECT_NEAR(elements, 2730, 1);
    EXPECT_NEAR(first["bytes_per_second"].get<double>() * t, 24 * 2730, 24);
    // The median aggregate follows the repetitions; latency has ns_per_load rather than bytes.
    bool median_seen = false, latency_seen = false;
    for (const auto& b : bs) {
        if (b["run_type"] == "aggregate" && b["aggregate_name"] == "median") median_seen = true;
        if (b["run_name"].get<std::string>().rfind("latency/", 0) == 0 && b["run_type"] == "iteration") {
            latency_seen = true;
            EXPECT_TRUE(b.contains("ns_per_load")) << b.dump();
            EXPECT_FALSE(b.contains("bytes_per_second")) << b.dump();
        }
    }
    EXPECT_TRUE(median_seen);
    EXPECT_TRUE(latency_seen);
}

#ifdef SUITE_GBENCH_BINARY
TEST(SuiteGbench, EveryKernelAndPatternIsABenchmark) {
    Outcome r = run_program({SUITE_GBENCH_BINARY, "--sizes=64KiB", "--threads=1", "--benchmark_list_tests"}, 60);
    ASSERT_EQ(r.status, 0) << describe(r);
    // The kernels of the real program (this test binary registers test-only kernels too).
    Outcome list = run_suite({"list", "--json"});
    ASSERT_EQ(list.status, 0) << describe(list);
    const json kernels = json::parse(list.out);
    ASSERT_FALSE(kernels.empty());
    for (const auto& k : kernels)
        for (const auto& a : k["accesses"])
            for (const auto& v : k["variants"]) {
                if (v == "nt" || v == "rep") continue;  // the store variants: sequential only, below
                const std::string access = a == "strided" ? std::string("strided:8") : a.get<std::string>();
                // Every variant is a benchmark of its own (sfc-build-keys, fem-assembly-colour).
                const std::string kernel = k["name"].get<std::string>() + (v == "" ? "" : "-" + v.get<std::string>());
                // Kernels sized by a count (meshes) keep their own sizes: --sizes is in bytes.
                const std::string prefix = kernel + "/" + access + "/";
                const std::string name = k["size"] == "count" ? prefix : prefix + "64KiB/1/real_time\n";
                EXPECT_NE(r.out.find(name), std::string::npos) << name << "\n" << r.out;
            }
    EXPECT_NE(r.out.find("copy-nt/sequential/64KiB/1/real_time"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("store-rep/sequential/64KiB/1/real_time"), std::string::npos) << r.out;
    EXPECT_EQ(r.out.find("copy-nt/random"), std::string::npos) << "nt has no random form\n" << r.out;
}

TEST(SuiteGbench, FilterRepetitionsAndJsonWork) {
    TempDir dir;
    Outcome r =
        run_program({SUITE_GBENCH_BINARY, "--sizes=256KiB", "--threads=1",
                     "--benchmark_filter=^add/(sequential|random)/", "--benchmark_repetitions=2",
                     "--benchmark_min_time=0.01", "--benchmark_format=json", "--benchmark_out=" + dir.file("gb.json")},
                    120);
    ASSERT_EQ(r.status, 0) << describe(r);
    const json doc = json::parse(slurp(dir.file("gb.json")));
    std::set<std::string> runs;
    for (const auto& b : doc["benchmarks"]) {
        expect_gbench_entry(b);
        runs.insert(b["run_name"].get<std::string>());
        if (b["run_type"] == "iteration") {
            ASSERT_TRUE(b.contains("bytes_per_second") && b.contains("items_per_second")) << b.dump();
            // bytes per second over items per second is add's 24 B per element.
            EXPECT_NEAR(b["bytes_per_second"].get<double>() / b["items_per_second"].get<double>(), 24.0, 0.01)
                << b.dump();
            EXPECT_FALSE(b.value("error_occurred", false)) << b.dump();
        }
    }
    EXPECT_EQ(runs, (std::set<std::string>{"add/sequential/256KiB/1/real_time", "add/random/256KiB/1/real_time"}));
}

TEST(SuiteGbench, ItsOwnBadOptionsAreRefused) {
    Outcome r = run_program({SUITE_GBENCH_BINARY, "--sizes=12XB"}, 30);
    EXPECT_EQ(r.status, 2) << describe(r);
    EXPECT_NE(r.err.find("suite-gbench: error:"), std::string::npos) << describe(r);
}
#endif
