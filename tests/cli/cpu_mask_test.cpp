// The CPU mask the suite is started with (taskset here; a cgroup or a batch scheduler on the
// users' machines) is the machine it was given: `all`, `compact` and the default sweep use the
// allowed CPUs only, an explicit CPU outside the mask is refused with the mask named, and the
// record shows the mask.
#include <unistd.h>

#include <algorithm>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tests/process.hpp"

using namespace suite::test;
using nlohmann::json;

namespace {

// Runs the suite under `taskset -c CPU`, CPU being the machine's last online CPU (so that
// CPU 0 is outside the mask); skips where the machine has one CPU.
Outcome run_masked(const std::vector<std::string>& args, int& cpu) {
    const long n = sysconf(_SC_NPROCESSORS_ONLN);
    cpu = static_cast<int>(n) - 1;
    std::vector<std::string> argv = {"/usr/bin/taskset", "-c", std::to_string(cpu), SUITE_BINARY};
    argv.insert(argv.end(), args.begin(), args.end());
    return run_program(argv, 120);
}

}  // namespace

TEST(CpuMask, AllAndTheDefaultSweepUseOnlyTheAllowedCpus) {
    if (sysconf(_SC_NPROCESSORS_ONLN) < 2) GTEST_SKIP() << "one CPU: no mask can leave one out";
    TempDir d;
    int cpu = -1;
    const Outcome r = run_masked({"--kernel=copy", "--size=64KiB", "--threads=all", "--reps=2", "--counters=none",
                                  "--energy=none", "--quiet", "--out=" + d.file("r.json")},
                                 cpu);
    ASSERT_EQ(r.status, 0) << describe(r);
    const json doc = json::parse(slurp(d.file("r.json")));
    const json& mask = doc["context"]["topology"]["cpu_mask"];
    EXPECT_EQ(mask["cpus"], std::to_string(cpu));
    EXPECT_TRUE(mask["restricted"].get<bool>());
    EXPECT_EQ(mask["machine_pus"].get<long>(), sysconf(_SC_NPROCESSORS_ONLN));
    EXPECT_EQ(doc["context"]["pus"], 1);
    ASSERT_EQ(doc["results"].size(), 1u) << "--threads=all is the one allowed CPU";
    const json& threads = doc["results"][0]["pin"]["threads"];
    ASSERT_EQ(threads.size(), 1u);
    EXPECT_EQ(threads[0]["cpu"], cpu);
    EXPECT_EQ(threads[0]["allowed_cpus"], json::array({cpu}));

    // The default thread sweep (1 and all) is one point per size, not two.
    const Outcome dry = run_masked({"--kernel=copy", "--size=64KiB", "--dry-run"}, cpu);
    ASSERT_EQ(dry.status, 0) << describe(dry);
    EXPECT_NE(dry.out.find("1 point(s)"), std::string::npos) << dry.out;
    EXPECT_EQ(dry.out.find("threads=2"), std::string::npos) << dry.out;
}

TEST(CpuMask, AnExplicitCpuOutsideTheMaskIsRefusedWithTheMaskNamed) {
    if (sysconf(_SC_NPROCESSORS_ONLN) < 2) GTEST_SKIP() << "one CPU: no mask can leave one out";
    int cpu = -1;
    const Outcome r = run_masked({"--kernel=copy", "--size=64KiB", "--pin=0", "--threads=1", "--dry-run"}, cpu);
    EXPECT_EQ(r.status, 2) << describe(r);
    EXPECT_TRUE(r.out.empty()) << describe(r);
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << describe(r);
    EXPECT_NE(r.err.find("--pin=0: CPU 0 is outside this process's CPU mask " + std::to_string(cpu)), std::string::npos)
        << r.err;
    // More threads than the mask allows: the message says why there are so few.
    const Outcome t = run_masked({"--kernel=copy", "--size=64KiB", "--threads=2", "--dry-run"}, cpu);
    EXPECT_EQ(t.status, 2) << describe(t);
    EXPECT_NE(t.err.find("CPU mask allows CPUs " + std::to_string(cpu)), std::string::npos) << t.err;
}

TEST(CpuMask, InfoShowsTheMask) {
    if (sysconf(_SC_NPROCESSORS_ONLN) < 2) GTEST_SKIP() << "one CPU: no mask can leave one out";
    int cpu = -1;
    const Outcome r = run_masked({"info"}, cpu);
    ASSERT_EQ(r.status, 0) << describe(r);
    EXPECT_NE(r.out.find("CPU mask: " + std::to_string(cpu) + ", 1 of the machine's"), std::string::npos) << r.out;
    // Unmasked, the record says so too.
    const Outcome full = run_suite({"info", "--json"});
    ASSERT_EQ(full.status, 0) << describe(full);
    const json j = json::parse(full.out);
    EXPECT_FALSE(j["cpu_mask"]["restricted"].get<bool>()) << j["cpu_mask"].dump();
}
