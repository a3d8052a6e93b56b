// The noise flag: /proc read from fixture trees (so every branch runs on any machine), the
// thresholds judged on hand-made snapshots, and the real signal on this machine: a busy process
// sharing the CPU of a timed loop makes the loop's point unstable.
#include <gtest/gtest.h>

#include <sched.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>

#include "harness/instruments/machine_load.hpp"
#include "tests/process.hpp"

using namespace suite;
using namespace suite::test;

namespace {

void write(const std::string& path, const std::string& text) {
    std::filesystem::create_directories(std::filesystem::path(path).parent_path());
    std::ofstream(path) << text;
}

// A /proc with two CPUs and two threads of this process.
void fake_proc(const std::string& root, std::uint64_t busy0, std::uint64_t idle0, std::uint64_t steal0,
               double wait_ns) {
    write(root + "/stat",
          "cpu  900 0 300 5000 10 0 5 40 0 0\n"
          "cpu0 " +
              std::to_string(busy0) + " 0 0 " + std::to_string(idle0) + " 0 0 0 " + std::to_string(steal0) +
              " 0 0\n"
              "cpu1 100 10 20 3000 5 1 2 7 0 0\n"
              "intr 12345 0 0\n");
    write(root + "/loadavg", "1.25 0.80 0.40 3/200 4242\n");
    write(root + "/self/task/10/schedstat", "5000000 " + std::to_string(static_cast<long long>(wait_ns)) + " 12\n");
    write(root + "/self/task/11/schedstat", "7000000 1000000 3\n");
}

LoadSnapshot snapshot(double wall, std::uint64_t busy, std::uint64_t idle, std::uint64_t steal, double process_cpu_s,
                      double run_delay_s) {
    LoadSnapshot s;
    s.have_stat = true;
    s.cpus = {busy, idle, steal};
    s.process_cpu_s = process_cpu_s;
    s.wall_s = wall;
    s.run_delay_s = run_delay_s;
    s.load_average = 0.5;
    return s;
}

const std::vector<double> steady = {1.00, 1.01, 0.99, 1.00, 1.02, 0.98, 1.00};

}  // namespace

TEST(MachineLoad, ReadsTheTeamsCpusTheRunQueueWaitAndTheLoadAverageFromProc) {
    TempDir dir;
    const std::string root = dir.file("proc");
    fake_proc(root, 400, 2000, 30, 2000000);
    const LoadSnapshot one = take_load_snapshot({0}, root);
    ASSERT_TRUE(one.have_stat);
    EXPECT_EQ(one.cpus.busy, 400u);  // user + nice + system + irq + softirq
    EXPECT_EQ(one.cpus.idle, 2000u);
    EXPECT_EQ(one.cpus.steal, 30u);
    ASSERT_TRUE(one.load_average.has_value());
    EXPECT_DOUBLE_EQ(*one.load_average, 1.25);
    ASSERT_TRUE(one.run_delay_s.has_value());
    EXPECT_NEAR(*one.run_delay_s, 3e-3, 1e-12);  // both threads' waits, in seconds
    const LoadSnapshot both = take_load_snapshot({0, 1}, root);
    EXPECT_EQ(both.cpus.busy, 400u + 100 + 10 + 20 + 1 + 2);
    EXPECT_EQ(both.cpus.idle, 2000u + 3000 + 5);
    EXPECT_EQ(both.cpus.steal, 37u);
    // Every CPU when none is named; the aggregate "cpu" line is not counted twice.
    EXPECT_EQ(take_load_snapshot({}, root).cpus.total(), both.cpus.total());
    // A CPU the file lacks: /proc/stat cannot be judged for that team.
    EXPECT_FALSE(take_load_snapshot({0, 5}, root).have_stat);
}

TEST(MachineLoad, MissingOrGarbledProcFilesAreNotMeasuredNeverZero) {
    TempDir dir;
    const LoadSnapshot none = take_load_snapshot({0}, dir.file("no-proc"));
    EXPECT_FALSE(none.have_stat);
    EXPECT_FALSE(none.load_average.has_value());
    EXPECT_FALSE(none.run_delay_s.has_value());
    write(dir.file("bad/stat"), "cpu0 twelve\ncpuX 1 2 3 4 5 6 7 8\n");
    write(dir.file("bad/loadavg"), "-3 x\n");
    write(dir.file("bad/self/task/1/schedstat"), "nonsense\n");
    const LoadSnapshot bad = take_load_snapshot({0}, dir.file("bad"));
    EXPECT_FALSE(bad.have_stat);
    EXPECT_FALSE(bad.load_average.has_value());
    EXPECT_FALSE(bad.run_delay_s.has_value());
    // Judged from such snapshots, only the spread can speak; the rest stays unjudged (null).
    const Stability st = assess_stability(none, none, steady, 1);
    EXPECT_FALSE(st.unstable);
    EXPECT_FALSE(st.steal_fraction.has_value());
    EXPECT_FALSE(st.others_fraction.has_value());
    EXPECT_FALSE(st.waited_fraction.has_value());
}

TEST(MachineLoad, EachThresholdFlagsThePointWithItsReason) {
    // One second, two CPUs at 100 ticks/s: 200 ticks. This process used 1.9 s of CPU.
    const LoadSnapshot b = snapshot(10.0, 1000, 1000, 0, 5.0, 0.0);
    const Stability quiet = assess_stability(b, snapshot(11.0, 1195, 1005, 0, 6.9, 0.01), steady, 2);
    EXPECT_FALSE(quiet.unstable) << (quiet.reasons.empty() ? "" : quiet.reasons[0].text);
    EXPECT_NEAR(*quiet.others_fraction, (195 - 190) / 200.0, 1e-12);
    EXPECT_NEAR(*quiet.waited_fraction, 0.01 / 2, 1e-12);
    EXPECT_NEAR(*quiet.steal_fraction, 0.0, 1e-12);
    EXPECT_NEAR(quiet.window_s, 1.0, 1e-12);

    // Another process took 60 of the 200 ticks.
    const Stability others = assess_stability(b, snapshot(11.0, 1195, 1005, 0, 6.35, 0.0), steady, 2);
    ASSERT_TRUE(others.unstable);
    EXPECT_NEAR(*others.others_fraction, 0.30, 1e-9);
    EXPECT_NE(others.reasons.at(0).text.find("other tasks took 30%"), std::string::npos) << others.reasons[0].text;

    // The hypervisor stole 20 ticks.
    const Stability steal = assess_stability(b, snapshot(11.0, 1175, 1005, 20, 6.75, 0.0), steady, 2);
    ASSERT_TRUE(steal.unstable);
    EXPECT_NE(steal.reasons.at(0).text.find("stole 10%"), std::string::npos) << steal.reasons[0].text;

    // The team's two threads waited 0.4 s in all for a CPU: 20 % of 2 x 1 s.
    const Stability waited = assess_stability(b, snapshot(11.0, 1195, 1005, 0, 6.9, 0.4), steady, 2);
    ASSERT_TRUE(waited.unstable);
    EXPECT_NE(waited.reasons.at(0).text.find("waited for a CPU 20%"), std::string::npos) << waited.reasons[0].text;

    // Repetitions that spread: half of them 30 % slower.
    const Stability spread =
        assess_stability(b, snapshot(11.0, 1195, 1005, 0, 6.9, 0.0), {1.0, 1.3, 1.0, 1.3, 1.0, 1.3}, 2);
    ASSERT_TRUE(spread.unstable);
    EXPECT_GT(spread.spread, 0.10);
    EXPECT_NE(spread.reasons.at(0).text.find("the repetitions spread"), std::string::npos) << spread.reasons[0].text;

    // The thresholds are the caller's.
    StabilityThresholds lax;
    lax.others = 0.5;
    EXPECT_FALSE(assess_stability(b, snapshot(11.0, 1195, 1005, 0, 6.35, 0.0), steady, 2, lax).unstable);
}

TEST(MachineLoad, AWindowOfAFewTicksIsNotJudgedByProcStat) {
    // 40 ms on one CPU: 4 ticks, every one of them busy with something else. Too coarse to judge.
    const LoadSnapshot b = snapshot(1.0, 100, 100, 0, 0.0, 0.0);
    const Stability st = assess_stability(b, snapshot(1.04, 104, 100, 0, 0.0, 0.0), steady, 1);
    EXPECT_FALSE(st.others_fraction.has_value());
    EXPECT_FALSE(st.unstable);
}

// The real signal: a busy child pinned to this thread's CPU takes half of it.
TEST(MachineLoad, ABusyProcessOnTheTeamsCpuMakesThePointUnstable) {
    cpu_set_t old_mask;
    ASSERT_EQ(sched_getaffinity(0, sizeof old_mask, &old_mask), 0);
    const int cpu = sched_getcpu();
    ASSERT_GE(cpu, 0);
    cpu_set_t one;
    CPU_ZERO(&one);
    CPU_SET(cpu, &one);
    ASSERT_EQ(sched_setaffinity(0, sizeof one, &one), 0);
    const pid_t child = fork();
    ASSERT_GE(child, 0);
    if (child == 0) {  // inherits the one-CPU mask
        volatile unsigned long spin = 0;
        for (;;) spin = spin + 1;
    }
    const LoadSnapshot before = take_load_snapshot({cpu});
    std::vector<double> samples;
    const auto end = std::chrono::steady_clock::now() + std::chrono::milliseconds(400);
    while (std::chrono::steady_clock::now() < end) {
        const auto t0 = std::chrono::steady_clock::now();
        volatile int sink = 0;
        for (int i = 0; i < 100000; ++i) sink = sink + i;
        samples.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    }
    const LoadSnapshot after = take_load_snapshot({cpu});
    kill(child, SIGKILL);
    waitpid(child, nullptr, 0);
    sched_setaffinity(0, sizeof old_mask, &old_mask);
    const Stability st = assess_stability(before, after, samples, 1);
    EXPECT_TRUE(st.unstable) << "window " << st.window_s << " s";
    if (after.run_delay_s) {
        ASSERT_TRUE(st.waited_fraction.has_value());
        EXPECT_GT(*st.waited_fraction, 0.2);  // about half, the other half is the child's
    } else {
        std::cout << "[ note ] no /proc/self/task/*/schedstat here: the run-queue wait is not measured\n";
        ASSERT_TRUE(st.others_fraction.has_value());
        EXPECT_GT(*st.others_fraction, 0.2);
    }
    EXPECT_GT(st.involuntary_switches, 0);
}
