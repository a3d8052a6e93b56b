// bench/vs_likwid.py --quick end to end, in seconds: the suite, the plain-loop reference and (where
// Debian's likwid is installed; it is a bench dependency, not a test one) likwid-bench run side by
// side, and the JSON and markdown land where asked. No ratio is asserted: speed is shown by
// `make bench-vs`, not by a test.
#include <unistd.h>

#include <filesystem>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "process.hpp"

using namespace suite::test;
using json = nlohmann::json;

TEST(Bench, VsLikwidQuickRunsBothSidesAndWritesTheRatios) {
    TempDir dir;
    Outcome r = run_program({SUITE_PYTHON, std::string(SUITE_SOURCE_DIR) + "/bench/vs_likwid.py", "--quick", "--suite", SUITE_BINARY,
                             "--ref", SUITE_REF_RANDOM, "--out", dir.path().string()},
                            300);
    ASSERT_EQ(r.status, 0) << describe(r);
    const json doc = json::parse(slurp(dir.file("vs_likwid_quick.json")));
    EXPECT_TRUE(doc["quick"].get<bool>());
    // add and latency, random, at 32 KiB and 1 MiB, one thread: each side measured once, verified.
    ASSERT_EQ(doc["random"].size(), 4u) << doc.dump(1);
    for (const auto& row : doc["random"]) {
        EXPECT_EQ(row["suite"].size(), 1u);
        EXPECT_EQ(row["ref"].size(), 1u);
        EXPECT_GT(row["ratio"].get<double>(), 0);
    }
    const bool likwid = access("/usr/bin/likwid-bench", X_OK) == 0;
    EXPECT_EQ(doc["likwid_available"].get<bool>(), likwid);
    if (likwid) {
        ASSERT_EQ(doc["likwid"].size(), 4u) << doc.dump(1);
        for (const auto& row : doc["likwid"]) {
            EXPECT_GT(row["ratio"].get<double>(), 0);
            // The same CPUs on both sides, read back from each program.
            EXPECT_EQ(row["suite_cpus"], row["likwid_cpus"]) << row.dump();
        }
        EXPECT_TRUE(doc["pinning_mismatches"].empty());
    } else {
        EXPECT_TRUE(doc["likwid"].empty());
        EXPECT_NE(r.out.find("likwid-bench comparison is left out"), std::string::npos) << r.out;
    }
    const std::string md = slurp(dir.file("vs_likwid_quick.md"));
    EXPECT_NE(md.find("| size | threads |"), std::string::npos) << md;
}
