// The cache probe on this machine, quickly: `suite info --probe` finds at least the L1 that
// hwloc reports, and `suite run --probe-caches` records what it found in the context (valid
// against the schema) and sizes the default sweep's DRAM point by it. No timing is asserted.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "harness/machine/topology.hpp"
#include "harness/measure/plan.hpp"
#include "tests/process.hpp"

using namespace suite::test;
using json = nlohmann::json;

TEST(CacheProbe, InfoProbeFindsTheFirstLevelWhereHwlocSaysItIs) {
    // A timing measurement, run beside the other tests (ctest -j 2): a probe whose sweep another
    // process disturbed may miss the step once. Up to three probes; every one must be well
    // formed, and one of them must find the L1 where hwloc says it is.
    const suite::Topology topo = suite::Topology::load();
    const suite::Cache* reported = topo.find_cache(1);
    std::string seen;
    for (int attempt = 0; attempt < 3; ++attempt) {
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
        if (!reported || !l1["capacity_bytes"].is_number())
            GTEST_SKIP() << "hwloc reports no L1 here, or the sweep ended in it";
        // Every L1 data cache is seen by a pointer chase, whatever a VM does to the last level.
        const double ratio = l1["capacity_bytes"].get<double>() / static_cast<double>(reported->size_bytes);
        if (ratio > 0.5 && ratio < 2.0) return;
        seen += "\nprobe " + std::to_string(attempt + 1) + ": " + m["levels"].dump();
    }
    ADD_FAILURE() << "no probe of three found the L1 within 2x of hwloc's " << reported->size_bytes << " B:" << seen;
}

TEST(CacheProbe, RunWithProbeCachesRecordsThemAndSizesTheDramPointByThem) {
    TempDir dir;
    const std::string out = dir.file("r.json");
    Outcome r =
        run_suite({"--probe-caches", "--kernel=load", "--threads=1", "--reps=1", "--quiet", "--out=" + out}, 300);
    ASSERT_EQ(r.status, 0) << describe(r);
    const json doc = json::parse(slurp(out));
    const json& m = doc["context"]["caches_measured"];
    ASSERT_TRUE(m.is_object());
    Outcome v = validate_against_schema(out);
    EXPECT_EQ(v.status, 0) << v.out << v.err;
    suite::MeasuredCaches measured;
    if (m["last_level_total_bytes"].is_number()) measured.llc_total = m["last_level_total_bytes"];
    for (const auto& l : m["levels"]) {
        if (l["partial"].get<bool>() || !l["capacity_bytes"].is_number()) continue;
        if (l["level"] == 1) measured.l1 = l["capacity_bytes"];
        if (l["level"] == 2) measured.l2 = l["capacity_bytes"];
    }
    const auto topo = suite::Topology::load();
    const auto expected = suite::default_sizes(topo, 1, measured);
    ASSERT_EQ(doc["results"].size(), expected.size());
    const auto reported_only = suite::default_sizes(topo, 1);
    for (std::size_t i = 0; i < expected.size(); ++i) {
        EXPECT_EQ(doc["results"][i]["size"]["requested"].get<std::uint64_t>(), expected[i]) << i;
        // Never larger than what the reported caches alone would ask for.
        EXPECT_LE(expected[i], reported_only[i]) << i;
    }
}

TEST(CacheProbe, DryRunDoesNotProbeAndSaysSo) {
    Outcome r = run_suite({"--probe-caches", "--kernel=load", "--threads=1", "--dry-run"});
    ASSERT_EQ(r.status, 0) << describe(r);
    EXPECT_NE(r.err.find("--probe-caches does not run with --dry-run"), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find("probing the caches"), std::string::npos) << r.err;
}

TEST(CacheProbe, DefaultSizesTakeTheSmallerOfReportedAndMeasured) {
    suite::Topology t;
    t.caches = {{1, "data", 48 << 10, 64, 2, 1}, {2, "unified", 1 << 20, 64, 2, 1}, {3, "unified", 32 << 20, 64, 1, 2}};
    // Reported only: half an L1d, half an L2, 16x the L3 (512 MiB).
    EXPECT_EQ(suite::default_sizes(t, 1), (std::vector<std::uint64_t>{24 << 10, 512 << 10, 512ull << 20}));
    // The development VM as probed: L1 46 KiB, L2 772 KiB, last level 2.03 MiB in all; the
    // measured last level adds its half (in whole lines) where it exceeds the L2 size.
    suite::MeasuredCaches m{46 << 10, 772 << 10, 2128609};
    EXPECT_EQ(suite::default_sizes(t, 1, m), (std::vector<std::uint64_t>{23 << 10, 386 << 10, 1064256, 64ull << 20}));
    EXPECT_EQ(suite::default_sizes(t, 2, m), (std::vector<std::uint64_t>{46 << 10, 772 << 10, 1064256, 64ull << 20}));
    EXPECT_EQ(suite::default_sizes(t, 3, m), (std::vector<std::uint64_t>{69 << 10, 1158 << 10, 64ull << 20}))
        << "half the last level within three threads' L2 halves has no point of its own";
    // A measured cache larger than the reported one changes nothing; the DRAM size rounds up to MiB.
    suite::MeasuredCaches bigger{64 << 10, 2 << 20, 6'000'000};
    EXPECT_EQ(suite::default_sizes(t, 1, bigger),
              (std::vector<std::uint64_t>{24 << 10, 512 << 10, 3'000'000, 92ull << 20}));
    EXPECT_EQ(suite::effective_llc_bytes(t, 0), 32ull << 20);
    EXPECT_EQ(suite::effective_llc_bytes(t, 6'000'000), 6'000'000u);
}
