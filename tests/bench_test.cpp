// bench/vs_likwid.py --quick end to end, in seconds: the suite, the plain-loop reference and (where
// Debian's likwid is installed; it is a bench dependency, not a test one) likwid-bench run side by
// side, and the JSON and markdown land where asked. No ratio is asserted: speed is shown by
// `make bench-vs`, not by a test.
#include <unistd.h>

#include <filesystem>
#include <set>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tests/process.hpp"

using namespace suite::test;
using json = nlohmann::json;

// bench/vs_peers.py --quick: every kind's best suite variant against its best peer at 32 KiB and
// 1 MiB on one thread; ref_stream's kernels verified (the script stops on a failed check).
TEST(Bench, VsPeersQuickHoldsEveryKindAgainstItsPeers) {
    TempDir dir;
    Outcome r = run_program({SUITE_PYTHON, std::string(SUITE_SOURCE_DIR) + "/bench/vs_peers.py", "--quick", "--suite",
                             SUITE_BINARY, "--ref", SUITE_REF_STREAM, "--out", dir.path().string()},
                            300);
    ASSERT_EQ(r.status, 0) << describe(r);
    const json doc = json::parse(slurp(dir.file("vs_peers_quick.json")));
    const bool likwid = access("/usr/bin/likwid-bench", X_OK) == 0;
    std::set<std::string> kinds;
    for (const auto& row : doc["rows"]) {
        kinds.insert(row["kind"].get<std::string>());
        EXPECT_GT(row["ratio"].get<double>(), 0) << row.dump();
        const double mine = row["suite"][row["suite_best"].get<std::string>()],
                     theirs = row["peers"][row["peer_best"].get<std::string>()];
        EXPECT_NEAR(row["ratio"].get<double>(), mine / theirs, 1e-12);
        for (const auto& [name, v] : row["peers"].items()) EXPECT_LE(v.get<double>(), theirs) << name;
        // copy and store against glibc's string functions, with the suite's own string-instruction variants.
        if (row["kind"] == "copy") {
            EXPECT_TRUE(row["peers"].contains("ref:memcpy") && row["suite"].contains("copy-rep")) << row.dump();
        }
        if (row["kind"] == "store") {
            EXPECT_TRUE(row["peers"].contains("ref:memset") && row["suite"].contains("store-rep")) << row.dump();
        }
        if (row["kind"] == "copy" && likwid) {
            EXPECT_TRUE(row["peers"].contains("likwid:copy")) << row.dump();
        }
    }
    std::set<std::string> want{"copy", "scale", "add", "triad", "store"};
    if (likwid) want.insert("load");  // its only peer is likwid-bench's
    EXPECT_EQ(kinds, want);
    EXPECT_EQ(doc["rows"].size(), 2 * kinds.size());
    // Without likwid-bench the run says so, on stderr and in both outputs, rather than passing
    // for a comparison with every peer.
    const std::string table = slurp(dir.file("vs_peers_quick.md"));
    if (likwid) {
        EXPECT_TRUE(doc["peers_left_out"].is_null()) << doc["peers_left_out"].dump();
        EXPECT_EQ(table.find("Not a comparison with every peer"), std::string::npos) << table;
    } else {
        EXPECT_NE(doc["peers_left_out"].get<std::string>().find("likwid-bench not found"), std::string::npos);
        EXPECT_NE(table.find("Not a comparison with every peer: likwid-bench not found"), std::string::npos) << table;
        EXPECT_NE(r.err.find("vs_peers: likwid-bench not found"), std::string::npos) << r.err;
    }
}

// --kinds: a focused re-run of some kinds, to a file of its own that leaves the whole table alone;
// a kind it does not know is refused before anything runs.
TEST(Bench, VsPeersKindsRunsThoseKindsAloneAndRefusesOthers) {
    TempDir dir;
    const std::string script = std::string(SUITE_SOURCE_DIR) + "/bench/vs_peers.py";
    Outcome r = run_program({SUITE_PYTHON, script, "--quick", "--kinds=scale,store", "--suite", SUITE_BINARY, "--ref",
                             SUITE_REF_STREAM, "--out", dir.path().string()},
                            300);
    ASSERT_EQ(r.status, 0) << describe(r);
    EXPECT_FALSE(std::filesystem::exists(dir.file("vs_peers_quick.json")));
    const json doc = json::parse(slurp(dir.file("vs_peers_quick_scale-store.json")));
    std::set<std::string> kinds;
    for (const auto& row : doc["rows"]) kinds.insert(row["kind"].get<std::string>());
    EXPECT_EQ(kinds, (std::set<std::string>{"scale", "store"}));
    EXPECT_EQ(doc["rows"].size(), 4u) << doc.dump(1);  // 32 KiB and 1 MiB each

    // Without likwid-bench, the line names what is missing from these kinds only: load is not asked for.
    r = run_program({SUITE_PYTHON, script, "--quick", "--kinds=scale", "--suite", SUITE_BINARY, "--ref",
                     SUITE_REF_STREAM, "--likwid", dir.file("no-likwid-bench"), "--out", dir.path().string()},
                    300);
    ASSERT_EQ(r.status, 0) << describe(r);
    EXPECT_NE(r.err.find("vs_peers: likwid-bench not found at " + dir.file("no-likwid-bench") +
                         ": its peers are left out (`make bench-deps` installs it)\n"),
              std::string::npos)
        << r.err;

    r = run_program({SUITE_PYTHON, script, "--kinds=copy,lod", "--suite", SUITE_BINARY, "--out", dir.path().string()},
                    60);
    EXPECT_EQ(r.status, 2) << describe(r);
    EXPECT_EQ(r.err,
              "vs_peers: --kinds=copy,lod: unknown kind lod; accepted: a comma-separated subset of copy, scale, add, "
              "triad, load, store\n");
}

TEST(Bench, VsLikwidQuickRunsBothSidesAndWritesTheRatios) {
    TempDir dir;
    Outcome r = run_program({SUITE_PYTHON, std::string(SUITE_SOURCE_DIR) + "/bench/vs_likwid.py", "--quick", "--suite",
                             SUITE_BINARY, "--ref", SUITE_REF_RANDOM, "--out", dir.path().string()},
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

// bench/aa_noise.py --quick: each program against itself, the JSON it writes holds one pair of
// measured figures per point and program, and the suite's points are its seven kernels.
TEST(Bench, AaNoiseQuickMeasuresEachProgramAgainstItself) {
    TempDir dir;
    Outcome r = run_program({SUITE_PYTHON, std::string(SUITE_SOURCE_DIR) + "/bench/aa_noise.py", "--quick", "--suite",
                             SUITE_BINARY, "--out", dir.path().string()},
                            300);
    ASSERT_EQ(r.status, 0) << describe(r);
    const json doc = json::parse(slurp(dir.file("aa_noise_quick.json")));
    EXPECT_EQ(doc["repetitions"].get<int>(), 1);
    EXPECT_EQ(doc["size_bytes"].get<std::uint64_t>(), 16u << 20);
    const bool likwid = access("/usr/bin/likwid-bench", X_OK) == 0;
    std::size_t suite_points = 0, likwid_points = 0;
    for (const auto& row : doc["points"]) {
        (row["program"] == "suite" ? suite_points : likwid_points) += 1;
        ASSERT_EQ(row["gbps_pairs"].size(), 1u) << row.dump();
        EXPECT_GT(row["gbps_pairs"][0][0].get<double>(), 0) << row.dump();
        EXPECT_GT(row["gbps_pairs"][0][1].get<double>(), 0) << row.dump();
        EXPECT_DOUBLE_EQ(row["ratio"].get<double>(),
                         row["gbps_pairs"][0][0].get<double>() / row["gbps_pairs"][0][1].get<double>());
    }
    EXPECT_EQ(suite_points, 7u);  // copy, copy-nt, triad, triad-nt, load, store, store-nt
    EXPECT_EQ(likwid_points, likwid ? 7u : 0u);
    EXPECT_NE(slurp(dir.file("aa_noise_quick.md")).find("suite against itself"), std::string::npos);

    r = run_program({SUITE_PYTHON, std::string(SUITE_SOURCE_DIR) + "/bench/aa_noise.py", "--reps", "0", "--suite",
                     SUITE_BINARY, "--out", dir.path().string()});
    EXPECT_EQ(r.status, 2);
    EXPECT_NE(r.err.find("--reps must be at least 1"), std::string::npos) << r.err;
}

// bench/gate_noise.py --quick: twelve copies of a fixture run, scaled by at most 1.2 %: no rule
// false-alarms on them, and each copy slowed 1.25x with its rerun fails the gate at
// --tolerance=auto --confirm in nearly every trial (these are the trials the note quotes on real reruns).
TEST(Bench, GateNoiseQuickHasNoFalseAlarmAndCatchesTheSlowdown) {
    TempDir dir;
    Outcome r = run_program({SUITE_PYTHON, std::string(SUITE_SOURCE_DIR) + "/bench/gate_noise.py", "--quick", "--suite",
                             SUITE_BINARY, "--out", dir.path().string()},
                            300);
    ASSERT_EQ(r.status, 0) << describe(r);
    const json doc = json::parse(slurp(dir.file("gate_noise_quick.json")));
    EXPECT_EQ(doc["runs"].get<int>(), 12);
    for (const auto& [rule, v] : doc["history_leave_one_out"].items()) {
        EXPECT_EQ(v["alarmed"].get<int>(), 0) << rule;
        EXPECT_GE(v["tried"].get<int>(), 11) << rule;
    }
    for (const auto& [tol, v] : doc["pairs_suite_check"].items()) EXPECT_EQ(v["tried"].get<int>(), 66) << tol;
    std::size_t failed = 0;
    for (const auto& t : doc["reach"]) failed += t["exit"] == "regressed";
    EXPECT_GE(failed, 10u) << doc["reach"].dump();
    EXPECT_NE(slurp(dir.file("gate_noise_quick.md")).find("auto, confirmed by a rerun"), std::string::npos);
    r = run_program({SUITE_PYTHON, std::string(SUITE_SOURCE_DIR) + "/bench/gate_noise.py", "--runs", "3", "--suite",
                     SUITE_BINARY, "--out", dir.path().string()});
    EXPECT_EQ(r.status, 2);
    EXPECT_NE(r.err.find("--runs must be at least 6"), std::string::npos) << r.err;
}

// bench/gate_reach.py --quick: ten copies of a fixture run, 5 % apart at most, as 9 pairs each
// gated against six others: no unchanged pair fails the gate, and both runs of every pair slowed
// 2x regress at every point.
TEST(Bench, GateReachQuickHasNoFalseAlarmAndCatchesA2xSlowdownEverywhere) {
    TempDir dir;
    Outcome r = run_program({SUITE_PYTHON, std::string(SUITE_SOURCE_DIR) + "/bench/gate_reach.py", "--quick", "--suite",
                             SUITE_BINARY, "--out", dir.path().string()},
                            300);
    ASSERT_EQ(r.status, 0) << describe(r);
    const json doc = json::parse(slurp(dir.file("gate_reach_quick.json")));
    EXPECT_EQ(doc["trials"].get<int>(), 9);
    EXPECT_EQ(doc["aa_pairs_with_a_false_alarm"].get<int>(), 0);
    ASSERT_EQ(doc["points"].size(), 3u);
    for (const auto& p : doc["points"]) EXPECT_EQ(p["caught_2.0"].get<int>(), 9) << p.dump();
    EXPECT_NE(slurp(dir.file("gate_reach_quick.md")).find("A/A (both runs unchanged): 0 of 9 pairs"),
              std::string::npos);
    r = run_program({SUITE_PYTHON, std::string(SUITE_SOURCE_DIR) + "/bench/gate_reach.py", "--runs", "5", "--suite",
                     SUITE_BINARY, "--out", dir.path().string()});
    EXPECT_EQ(r.status, 2);
    EXPECT_NE(r.err.find("--runs must be at least 8"), std::string::npos) << r.err;
}

// bench/mpm_implicit.py --quick: a step of implicit MPM split into assembly, solve and the rest,
// for every grid ordering and both particle orders, from the three kernels' records. No speed is
// asserted; that each part was found and is consistent with the step's counts is.
TEST(Bench, MpmImplicitQuickSplitsAStepIntoItsParts) {
    TempDir dir;
    Outcome r = run_program({SUITE_PYTHON, std::string(SUITE_SOURCE_DIR) + "/bench/mpm_implicit.py", "--quick",
                             "--suite", SUITE_BINARY, "--out", dir.path().string()},
                            300);
    ASSERT_EQ(r.status, 0) << describe(r);
    const json doc = json::parse(slurp(dir.file("mpm_implicit.json")));
    ASSERT_EQ(doc["points"].size(), 6u) << doc.dump(1);
    for (const char* key : {"natural/seeded", "natural/dynamic", "morton/seeded", "morton/dynamic", "hilbert/seeded",
                            "hilbert/dynamic"}) {
        const json& p = doc["points"][key];
        EXPECT_GT(p["step"].get<double>(), 0) << key;
        EXPECT_GT(p["assembly"].get<double>(), 0) << key;
        EXPECT_GT(p["solve"].get<double>(), 0) << key;
        EXPECT_NEAR(p["rest"].get<double>(),
                    p["step"].get<double>() - p["assembly"].get<double>() - p["solve"].get<double>(), 1e-12)
            << key;
        EXPECT_GE(p["newton"].get<double>(), 1) << key;
        EXPECT_GT(p["cg"].get<double>(), p["newton"].get<double>()) << key;  // more than one CG iteration a Newton step
        if (!p["cholmod"].is_null()) {
            EXPECT_GT(p["cholmod"].get<double>(), 0) << key;  // null where built without CHOLMOD
        }
    }
    const std::string md = slurp(dir.file("mpm_implicit.md"));
    EXPECT_NE(
        md.find("| grid / particles | step | assembly | solve (CG) | rest | Newton/step | CG/step | CHOLMOD factor |"),
        std::string::npos)
        << md;
}
