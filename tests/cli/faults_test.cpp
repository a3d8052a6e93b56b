// Nothing lost under faults: a full disk, a file size limit, an energy counter that vanishes
// mid-run; and the suite neither needs root nor changes the system when it has it.
#include <unistd.h>

#include <atomic>
#include <filesystem>
#include <fstream>
#include <thread>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tests/fake_rapl.hpp"
#include "tests/process.hpp"

namespace fs = std::filesystem;
using namespace suite::test;
using nlohmann::json;

namespace {

const std::string kFixtures = std::string(SUITE_SOURCE_DIR) + "/tests/fixtures/sysfs/";

// A previous result to protect: a real, valid one.
std::string write_previous(const TempDir& d, const std::string& path) {
    const Outcome r = run_suite({"--kernel=copy", "--size=64KiB", "--threads=1", "--reps=1", "--counters=none",
                                 "--energy=none", "--quiet", "--out=" + path});
    EXPECT_EQ(r.status, 0) << describe(r);
    (void)d;
    return slurp(path);
}

std::string shell_quote(const std::string& s) { return "'" + s + "'"; }

}  // namespace

TEST(Faults, FullDiskKeepsThePreviousFileAndSaysSo) {
    if (geteuid() != 0)
        GTEST_SKIP() << "mounting a small tmpfs needs root (a private mount namespace is used, nothing leaks)";
    TempDir d;
    const std::string mnt = d.file("small");
    fs::create_directory(mnt);
    // Inside a private mount namespace: a 64 KiB tmpfs, a previous result in it, then a run whose
    // document (every repetition time of 20 points) cannot fit in what is left.
    const std::string script =
        "set -e; mount -t tmpfs -o size=64k suite-test " + shell_quote(mnt) + "; " + shell_quote(SUITE_BINARY) +
        " --kernel=copy --size=64KiB --threads=1 --reps=1 --counters=none --energy=none --quiet --out=" +
        shell_quote(mnt + "/r.json") + "; cp " + shell_quote(mnt + "/r.json") + " " +
        shell_quote(d.file("before.json")) + "; head -c 56000 /dev/zero > " + shell_quote(mnt + "/filler") +
        "; set +e; " + shell_quote(SUITE_BINARY) +
        " --kernel=copy,scale,add,triad --sizes=16KiB:256KiB --threads=1 --reps=300 --counters=none --energy=none "
        "--quiet --out=" +
        shell_quote(mnt + "/r.json") + "; status=$?; cp " + shell_quote(mnt + "/r.json") + " " +
        shell_quote(d.file("after.json")) + "; ls -a " + shell_quote(mnt) + " > " + shell_quote(d.file("listing")) +
        "; exit $status";
    const Outcome r =
        run_program({"/usr/bin/unshare", "--mount", "--propagation", "private", "/bin/sh", "-c", script}, 120);
    if (r.status != 1 && r.err.find("mount") != std::string::npos && r.err.find("No space") == std::string::npos)
        GTEST_SKIP() << "cannot mount a tmpfs here: " << r.err;
    EXPECT_EQ(r.status, 1) << describe(r);
    EXPECT_NE(r.err.find("No space left on device"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("the previous file, if any, is unchanged"), std::string::npos) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_TRUE(slurp(d.file("after.json")) == slurp(d.file("before.json"))) << "the previous result file changed";
    EXPECT_EQ(slurp(d.file("listing")).find(".tmp"), std::string::npos) << "a temporary file was left behind:\n"
                                                                        << slurp(d.file("listing"));
}

TEST(Faults, FileSizeLimitIsAnErrorAndTheFileStaysValid) {
    // `ulimit -f` in the user's shell, every signal at its default (process.hpp starts programs
    // so): the suite ignores SIGXFSZ itself, so a write past the limit fails with EFBIG and it
    // says so (exit 1, one line) instead of dying by the signal (exit 153, nothing said). The
    // previous file stays as it was and no temporary or lock file is left.
    TempDir d;
    const std::string out = d.file("r.json");
    const std::string before = write_previous(d, out);
    // 4 blocks: 2 KiB for dash's 512-byte blocks, 4 KiB for bash's; the previous file is larger.
    ASSERT_GT(before.size(), 4096u);
    const std::string script =
        "ulimit -f 4; exec " + shell_quote(SUITE_BINARY) +
        " --kernel=copy,scale,add,triad --sizes=16KiB:256KiB --threads=1 --reps=3 --counters=none "
        "--energy=none --quiet --out=" +
        shell_quote(out);
    const Outcome r = run_program({"/bin/sh", "-c", script}, 120);
    EXPECT_EQ(r.term_signal, 0) << describe(r);
    EXPECT_EQ(r.status, 1) << describe(r);
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << describe(r);
    // The previous file holds a complete result: the run's interim records go beside it.
    EXPECT_NE(r.err.find("cannot write " + d.file("r.incomplete.json")), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("File too large"), std::string::npos) << r.err;
    EXPECT_TRUE(slurp(out) == before) << "the previous result file changed";
    for (const auto& e : fs::directory_iterator(d.path()))
        EXPECT_EQ(e.path().filename().string(), "r.json") << "left behind: " << e.path();
}

TEST(Faults, EnergyFileVanishingMidRunLosesThatPointOnlyAndTheRunGoesOn) {
    TempDir d;
    const std::string root = d.file("sys");
    fs::copy(kFixtures + "amd-epyc", root, fs::copy_options::recursive);
    MovingEnergyCounter pkg(root + "/class/powercap/intel-rapl:0/energy_uj", 1000, 500);
    const std::string out = d.file("r.json");
    // Once the result file holds two records, the energy file disappears for good.
    std::atomic<bool> done{false};
    std::thread remover([&] {
        while (!done) {
            try {
                if (fs::exists(out) && json::parse(slurp(out))["results"].size() >= 2) {
                    pkg.remove();
                    return;
                }
            } catch (const std::exception&) {  // not there yet
            }
            std::this_thread::sleep_for(std::chrono::milliseconds(2));
        }
    });
    setenv("SUITE_SYSFS_ROOT", root.c_str(), 1);
    // Points of 0.1 s each (not 5 repetitions of a few ms): the fake counter's thread advances
    // it every 50 us when it gets a CPU, and under a loaded CI it once got none during a whole
    // short point, which then read a counter that never moved.
    const Outcome r = run_suite({"--kernel=triad", "--sizes=1MiB,2MiB,3MiB,4MiB,5MiB", "--threads=1", "--min-time=0.1",
                                 "--energy=sysfs", "--counters=none", "--quiet", "--out=" + out},
                                120);
    unsetenv("SUITE_SYSFS_ROOT");
    done = true;
    remover.join();
    ASSERT_EQ(r.status, 0) << describe(r);
    const json doc = json::parse(slurp(out));
    ASSERT_EQ(doc["results"].size(), 5u);
    EXPECT_TRUE(doc["complete"].get<bool>());
    EXPECT_TRUE(doc["results"][0]["energy"]["domains"][0]["available"].get<bool>())
        << doc["results"][0]["energy"].dump();
    const json& last = doc["results"][4]["energy"]["domains"][0];
    EXPECT_FALSE(last["available"].get<bool>());
    EXPECT_NE(last["reason"].get<std::string>().find("during the run"), std::string::npos) << last.dump();
    EXPECT_TRUE(last["joules_per_call"].is_null());
}

TEST(Faults, RunsWithoutRoot) {
    if (geteuid() != 0) {
        // Every other test already runs unprivileged here.
        const Outcome r =
            run_suite({"--kernel=triad", "--size=1MiB", "--threads=1", "--reps=3", "--quiet", "--format=json"});
        EXPECT_EQ(r.status, 0) << describe(r);
        return;
    }
    TempDir d;
    fs::permissions(d.path(), fs::perms::all, fs::perm_options::add);  // the unprivileged user writes here
    const Outcome r = run_program(
        {"/usr/bin/setpriv", "--reuid=65534", "--regid=65534", "--clear-groups", SUITE_BINARY, "--kernel=triad,latency",
         "--size=1MiB", "--threads=1,2", "--reps=3", "--quiet", "--out=" + d.file("r.json")},
        120);
    if (r.status != 0 && r.err.find("Permission denied") != std::string::npos &&
        r.err.find("suite") == std::string::npos)
        GTEST_SKIP() << "uid 65534 cannot reach the binary here: " << r.err;
    ASSERT_EQ(r.status, 0) << describe(r);
    const json doc = json::parse(slurp(d.file("r.json")));
    EXPECT_EQ(doc["results"].size(), 4u);
    const json& c = doc["context"]["instruments"]["perf_counters"];
    EXPECT_FALSE(c["privileged"].get<bool>());
    for (const auto& rec : doc["results"]) {
        EXPECT_TRUE(rec["verification"]["passed"].get<bool>());
        EXPECT_TRUE(rec["pin"]["held_during_run"].get<bool>());
    }
}

TEST(Faults, AsRootItChangesNoSystemSetting) {
    const std::vector<std::string> settings = {"/proc/sys/kernel/perf_event_paranoid",
                                               "/proc/sys/kernel/numa_balancing",
                                               "/sys/kernel/mm/transparent_hugepage/enabled",
                                               "/sys/kernel/mm/transparent_hugepage/defrag",
                                               "/proc/sys/vm/overcommit_memory",
                                               "/proc/sys/kernel/randomize_va_space",
                                               "/sys/devices/system/cpu/cpu0/cpufreq/scaling_governor"};
    auto snapshot = [&] {
        std::vector<std::string> v;
        for (const auto& p : settings) v.push_back(fs::exists(p) ? slurp(p) : "(absent)");
        return v;
    };
    const auto before = snapshot();
    const Outcome r = run_suite({"--kernel=triad,add", "--pattern=sequential,random", "--size=2MiB", "--threads=1,2",
                                 "--reps=3", "--placement=interleave", "--quiet", "--format=json"});
    ASSERT_EQ(r.status, 0) << describe(r);
    const auto after = snapshot();
    for (std::size_t i = 0; i < settings.size(); ++i) EXPECT_EQ(before[i], after[i]) << settings[i];
}

TEST(Faults, OpenMpThreadLimitBelowTheAskedTeamIsAUsageErrorUpFront) {
    TempDir d;
    setenv("OMP_THREAD_LIMIT", "1", 1);
    const Outcome r = run_suite({"--kernel=triad", "--size=1MiB", "--threads=1,2", "--out=" + d.file("r.json")});
    unsetenv("OMP_THREAD_LIMIT");
    EXPECT_EQ(r.status, 2) << describe(r);
    EXPECT_NE(r.err.find("OMP_THREAD_LIMIT"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(d.file("r.json")));
}
