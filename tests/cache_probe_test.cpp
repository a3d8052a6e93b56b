// The cache probe on this machine, quickly: `suite info --probe` finds at least the L1 that
// hwloc reports, and `suite run --probe-caches` records what it found in the context (valid
// against the schema) and sizes the default sweep's DRAM point by it. No timing is asserted.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "harness/plan.hpp"
#include "harness/topology.hpp"
#include "process.hpp"

using namespace suite::test;
using json = nlohmann::json;

TEST(CacheProbe, InfoProbeFindsTheFirstLevelWhereHwlocSaysItIs) {
    Outcome r = run_suite({"info", "--probe", "--json"}, 300);
    ASSERT_EQ(r.status, 0) << describe(r);
    const json m = json::parse(r.out)["caches_measured"];
    ASSERT_TRUE(m.is_object()) << r.out;
    ASSERT_GE(m["latency_sweep"].size(), 10u);
    std::uint64_t previous = 0;
    for (const auto& p : m["latency_sweep"]) {
        EXPECT_GT(p["size_bytes"].get<std::uint64_t>(), previous);
        previous = p["size_bytes"];
        EXPECT_GT(p["ns"].get<double>(), 0);
    }
    EXPECT_EQ(m["bandwidth_sweep"].size(), m["latency_sweep"].size());
    ASSERT_GE(m["levels"].size(), 1u) << m.dump(1);
    const json& l1 = m["levels"][0];
    EXPECT_EQ(l1["level"], 1);
    EXPECT_FALSE(l1["partial"].get<bool>());
    const suite::Cache* reported = suite::Topology::load().find_cache(1);
    if (!reported || !l1["capacity_bytes"].is_number()) GTEST_SKIP() << "hwloc reports no L1 here, or the sweep ended in it";
    // Every L1 data cache is seen by a pointer chase, whatever a VM does to the last level.
    const double ratio = l1["capacity_bytes"].get<double>() / static_cast<double>(reported->size_bytes);
    EXPECT_GT(ratio, 0.5) << m["levels"].dump();
    EXPECT_LT(ratio, 2.0) << m["levels"].dump();
}

TEST(CacheProbe, RunWithProbeCachesRecordsThemAndSizesTheDramPointByThem) {
    TempDir dir;
    const std::string out = dir.file("r.json");
    Outcome r = run_suite({"--probe-caches", "--kernel=load", "--threads=1", "--reps=1", "--quiet", "--out=" + out}, 300);
    ASSERT_EQ(r.status, 0) << describe(r);
    const json doc = json::parse(slurp(out));
    const json& m = doc["context"]["caches_measured"];
    ASSERT_TRUE(m.is_object());
    Outcome v = validate_against_schema(out);
    EXPECT_EQ(v.status, 0) << v.out << v.err;
    const std::uint64_t measured = m["last_level_total_bytes"].is_number() ? m["last_level_total_bytes"].get<std::uint64_t>() : 0;
    const auto topo = suite::Topology::load();
    const auto expected = suite::default_sizes(topo, 1, measured);
    ASSERT_EQ(doc["results"].size(), expected.size());
    EXPECT_EQ(doc["results"].back()["size"]["requested"].get<std::uint64_t>(), expected.back());
    // Never larger than what the reported caches alone would ask for.
    EXPECT_LE(expected.back(), suite::default_sizes(topo, 1).back());
}

TEST(CacheProbe, DryRunDoesNotProbeAndSaysSo) {
    Outcome r = run_suite({"--probe-caches", "--kernel=load", "--threads=1", "--dry-run"});
    ASSERT_EQ(r.status, 0) << describe(r);
    EXPECT_NE(r.err.find("--probe-caches does not run with --dry-run"), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find("probing the caches"), std::string::npos) << r.err;
}
