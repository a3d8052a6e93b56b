// Counter plumbing with real software events (they need no PMU), the reasons given when an
// event cannot be counted, and hardware events where this machine has a PMU.
#include <sched.h>
#include <sys/mman.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>
#include <omp.h>

#include "harness/common/units.hpp"
#include "harness/instruments/counters.hpp"

using namespace suite;

namespace {

const EventReading& event(const CounterReadings& r, const std::string& name) {
    for (const auto& e : r.events)
        if (e.name == name) return e;
    throw std::runtime_error("no event " + name);
}

PerfAccess privileged() { return {2, true}; }
PerfAccess unprivileged(int paranoid) { return {paranoid, false}; }

// Whether this process can count a hardware event, and if not why.
std::string hardware_reason() {
    const auto sel = parse_counters("cycles", perf_access());
    return probe_event(sel.events.front(), perf_access());
}

}  // namespace

TEST(CounterNames, GenericAndSoftwareNamesResolveThroughLibpfm4) {
    const auto sel = parse_counters("cycles,LLC-load-misses,page-faults,cpu-migrations", privileged());
    ASSERT_EQ(sel.events.size(), 4u);
    EXPECT_EQ(sel.events[0].canonical, "perf::PERF_COUNT_HW_CPU_CYCLES");
    EXPECT_TRUE(sel.events[0].hardware);
    EXPECT_EQ(sel.events[1].canonical, "perf::PERF_COUNT_HW_CACHE_LL:READ:MISS");
    EXPECT_EQ(sel.events[2].attr.type, static_cast<std::uint32_t>(PERF_TYPE_SOFTWARE));
    EXPECT_FALSE(sel.events[2].hardware);
    EXPECT_FALSE(sel.events[2].kernel_mode_only);
    EXPECT_TRUE(sel.events[3].kernel_mode_only);
    EXPECT_EQ(sel.events[0].attr.exclude_kernel, 0u);
}

TEST(CounterNames, UserOnlyAccessExcludesKernelMode) {
    const auto sel = parse_counters("instructions", unprivileged(2));
    EXPECT_EQ(sel.events[0].attr.exclude_kernel, 1u);
}

TEST(CounterNames, UnknownDuplicateAndMixedNamesAreUsageErrors) {
    auto message = [](const std::string& text) {
        try {
            parse_counters(text, privileged());
        } catch (const UsageError& e) {
            return std::string(e.what());
        }
        return std::string("(accepted)");
    };
    EXPECT_NE(message("cycles,not-an-event").find("unknown counter event 'not-an-event'"), std::string::npos)
        << message("cycles,not-an-event");
    EXPECT_NE(message("cycles,cycles").find("names 'cycles' twice"), std::string::npos);
    EXPECT_NE(message("default,cycles").find("cannot be combined"), std::string::npos);
    EXPECT_NE(message("cycles,").find("empty event name"), std::string::npos);
    EXPECT_FALSE(parse_counters("none", privileged()).requested);
}

TEST(CounterNames, DefaultKeepsSoftwareEventsAndExplainsWhatItLeftOut) {
    const auto sel = parse_counters("default", perf_access());
    ASSERT_TRUE(sel.requested);
    std::vector<std::string> names;
    for (const auto& e : sel.events) names.push_back(e.name);
    for (const char* sw : {"task-clock", "page-faults"})
        EXPECT_NE(std::find(names.begin(), names.end(), sw), names.end()) << sw;
    EXPECT_EQ(sel.events.size() + sel.omitted.size(), 9u);
    for (const auto& [name, why] : sel.omitted) EXPECT_FALSE(why.empty()) << name;
    if (!hardware_reason().empty()) {
        ASSERT_GE(sel.omitted.size(), 5u) << "without a PMU the five hardware events are left out";
        EXPECT_EQ(sel.omitted.front().first, "cycles");
    }
}

TEST(CounterReasons, EachFailureSaysWhatToDo) {
    EXPECT_NE(open_failure_reason(EACCES, true, unprivileged(3)).find("perf_event_paranoid is 3"), std::string::npos);
    EXPECT_NE(open_failure_reason(EACCES, false, unprivileged(2)).find("perf_event_paranoid=2"), std::string::npos);
    EXPECT_NE(open_failure_reason(ENOENT, true, privileged()).find("no hardware PMU"), std::string::npos);
    EXPECT_NE(open_failure_reason(EMFILE, false, privileged()).find("ulimit -n"), std::string::npos);
    EXPECT_NE(open_failure_reason(EINVAL, true, privileged()).find("rejected"), std::string::npos);
}

TEST(CounterReasons, ParanoidLevelsDecideScopeAndRefusals) {
    EXPECT_EQ(unprivileged(1).scope(), "user+kernel");
    EXPECT_EQ(unprivileged(2).scope(), "user");
    EXPECT_EQ(PerfAccess({3, true}).scope(), "user+kernel");
    EXPECT_TRUE(unprivileged(3).forbidden());
    const auto sel = parse_counters("cpu-migrations,page-faults", privileged());
    // A user-only count of migrations would always be 0: refused, with the reason.
    EXPECT_NE(policy_refusal(sel.events[0], unprivileged(2)).find("kernel mode"), std::string::npos);
    EXPECT_EQ(policy_refusal(sel.events[0], unprivileged(1)), "");
    EXPECT_EQ(policy_refusal(sel.events[1], unprivileged(2)), "");
    EXPECT_NE(policy_refusal(sel.events[1], unprivileged(3)).find("forbids"), std::string::npos);
}

TEST(CounterScaling, MultiplexedCountsAreScaledAndUnscheduledOnesAreNotCounts) {
    EXPECT_DOUBLE_EQ(*scaled_count(1000, 500, 500), 1000.0);
    EXPECT_DOUBLE_EQ(*scaled_count(1000, 400, 100), 4000.0);  // on the PMU a quarter of the time
    EXPECT_DOUBLE_EQ(*scaled_count(7, 0, 0), 7.0);
    EXPECT_FALSE(scaled_count(0, 500, 0).has_value());  // never scheduled: not 0, unknown
}

TEST(CounterScaling, ARepetitionAThreadNeverCountedInHasNoTeamCount) {
    // Two threads, each multiplexed differently: each scaled by its own fraction.
    EXPECT_DOUBLE_EQ(*team_count({{100, 200, 100}, {300, 400, 400}}), 500.0);
    // Thread 1 was never on the PMU in this repetition: no count at all, not 100 and not 0.
    EXPECT_FALSE(team_count({{100, 200, 200}, {0, 200, 0}}).has_value());
    EXPECT_DOUBLE_EQ(*team_count({}), 0.0);
}

namespace {

// A captured-shape sysfs tree: QEMU's emulated Neoverse N1 PMU lists these four common events.
struct FakePmuTree {
    std::filesystem::path root = std::filesystem::temp_directory_path() / ("pmu-tree-" + std::to_string(getpid()));
    FakePmuTree() {
        const auto pmu = root / "bus/event_source/devices/armv8_pmuv3";
        std::filesystem::create_directories(pmu / "events");
        std::ofstream(pmu / "type") << "8\n";
        for (auto [name, code] : {std::pair{"cpu_cycles", "0x0011"},
                                  {"inst_retired", "0x0008"},
                                  {"stall_frontend", "0x0023"},
                                  {"stall_backend", "0x0024"}})
            std::ofstream(pmu / "events" / name) << "event=" << code << "\n";
        std::filesystem::create_directories(root / "bus/event_source/devices/software");
        std::ofstream(root / "bus/event_source/devices/software/type") << "1\n";
    }
    ~FakePmuTree() { std::filesystem::remove_all(root); }
};

perf_event_attr raw(std::uint32_t type, std::uint64_t config) {
    perf_event_attr a{};
    a.type = type;
    a.config = config;
    return a;
}

}  // namespace

TEST(CounterPmu, ACommonEventTheArmPmuDoesNotListIsUnavailableWithTheReason) {
    FakePmuTree tree;
    const std::string root = tree.root.string();
    EXPECT_EQ(unimplemented_event_reason(raw(PERF_TYPE_RAW, 0x08), root), "");           // INST_RETIRED
    EXPECT_EQ(unimplemented_event_reason(raw(8, 0x11), root), "");                       // by the PMU's own type
    const std::string why = unimplemented_event_reason(raw(PERF_TYPE_RAW, 0x03), root);  // L1D_CACHE_REFILL
    EXPECT_NE(why.find("does not implement event 0x03"), std::string::npos) << why;
    EXPECT_NE(why.find("armv8_pmuv3"), std::string::npos) << why;
    EXPECT_NE(why.find("cpu_cycles, inst_retired, stall_backend, stall_frontend"), std::string::npos) << why;
    EXPECT_NE(unimplemented_event_reason(raw(8, 0x4004), root), "");  // an extended common event
    // Implementation-defined numbers are never listed: their absence proves nothing.
    EXPECT_EQ(unimplemented_event_reason(raw(PERF_TYPE_RAW, 0x40), root), "");
    // Another PMU's type, and a machine with no Arm PMU (x86: its core PMU is "cpu").
    EXPECT_EQ(unimplemented_event_reason(raw(1, 0x03), root), "");
    EXPECT_EQ(unimplemented_event_reason(raw(PERF_TYPE_RAW, 0x03), root + "/nowhere"), "");
}

TEST(TeamCountersTest, FirstTouchOfNPagesCountsAtLeastNPageFaults) {
    const auto sel = parse_counters("page-faults,task-clock", perf_access());
    for (int threads : {1, 2}) {
        TeamCounters c(sel.events, threads, perf_access());
        const std::size_t pages = 512, page = static_cast<std::size_t>(sysconf(_SC_PAGESIZE));
        void* p = mmap(nullptr, pages * page, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
        ASSERT_NE(p, MAP_FAILED);
        madvise(p, pages * page, MADV_NOHUGEPAGE);  // one fault per 4 KiB page, not per 2 MiB
        c.start();
#pragma omp parallel for num_threads(threads) schedule(static)
        for (std::size_t i = 0; i < pages; ++i) static_cast<char*>(p)[i * page] = 1;
        c.stop();
        c.check_team();
        munmap(p, pages * page);
        const CounterReadings r = c.readings(1, static_cast<double>(pages), 0, 64);
        const EventReading& faults = event(r, "page-faults");
        ASSERT_TRUE(faults.available) << faults.reason;
        EXPECT_GE(faults.per_call.median, static_cast<double>(pages)) << threads << " thread(s)";
        EXPECT_LT(faults.per_call.median, 2.0 * pages) << threads << " thread(s)";
        EXPECT_GE(*faults.per_element, 1.0);
        EXPECT_FALSE(faults.multiplexed);
        EXPECT_DOUBLE_EQ(*faults.running_fraction, 1.0);
        EXPECT_TRUE(event(r, "task-clock").available);
        EXPECT_GT(event(r, "task-clock").per_call.median, 0);
    }
}

TEST(TeamCountersTest, MigrationsAreZeroWhenPinnedAndCountedWhenTheThreadMoves) {
    if (sysconf(_SC_NPROCESSORS_ONLN) < 2) GTEST_SKIP() << "needs 2 CPUs to move a thread between them";
    const auto sel = parse_counters("cpu-migrations", perf_access());
    if (const std::string why = policy_refusal(sel.events[0], perf_access()); !why.empty()) GTEST_SKIP() << why;
    cpu_set_t original;
    sched_getaffinity(0, sizeof original, &original);
    auto pin = [](int cpu) {
        cpu_set_t s;
        CPU_ZERO(&s);
        CPU_SET(cpu, &s);
        sched_setaffinity(0, sizeof s, &s);
    };
    pin(0);
    TeamCounters c(sel.events, 1, perf_access());  // one thread: the OpenMP master, this thread
    auto spin = [] {
        const auto t0 = std::chrono::steady_clock::now();
        volatile double x = 0;
        while (std::chrono::steady_clock::now() - t0 < std::chrono::milliseconds(20)) x = x + 1;
    };
    c.start();
    spin();
    c.stop();
    c.start();  // the control: the same counter must see a forced move
    pin(1);
    spin();
    pin(0);
    spin();
    c.stop();
    sched_setaffinity(0, sizeof original, &original);
    const CounterReadings r = c.readings(1, 1, 1, 64);
    const EventReading& m = event(r, "cpu-migrations");
    ASSERT_TRUE(m.available) << m.reason;
    EXPECT_EQ(m.per_call.min, 0.0) << "the pinned repetition";
    EXPECT_GE(m.per_call.max, 2.0) << "the repetition that moved from CPU 0 to 1 and back";
}

TEST(TeamCountersTest, HardwareEventsAreUnavailableWithTheReasonWithoutAPmu) {
    const std::string why = hardware_reason();
    if (why.empty())
        GTEST_SKIP() << "this machine has a PMU; the e2e test compares hardware counts with perf stat instead";
    const auto sel = parse_counters("cycles,instructions,page-faults", perf_access());
    TeamCounters c(sel.events, 2, perf_access());
    c.start();
    c.stop();
    const CounterReadings r = c.readings(1, 1, 1, 64);
    EXPECT_TRUE(r.available) << "page-faults can still be counted";
    for (const char* hw : {"cycles", "instructions"}) {
        EXPECT_FALSE(event(r, hw).available);
        EXPECT_EQ(event(r, hw).reason, why);
    }
    EXPECT_FALSE(r.ipc.has_value()) << "IPC needs both inputs";
    EXPECT_FALSE(r.llc_miss_bytes_per_call.has_value());
}

TEST(TeamCountersTest, EmptySelectionReadsNothing) {
    TeamCounters c;
    EXPECT_TRUE(c.empty());
    c.start();
    c.stop();
    c.check_team();
}
