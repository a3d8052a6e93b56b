#pragma once
// Event counters through perf_event_open, with event names resolved by libpfm4: the generic
// ones (cycles, LLC-load-misses, page-faults, ...) and those of the PMU this CPU has
// (MEM_LOAD_RETIRED:L3_MISS, ...). An event that cannot be counted is kept with the reason;
// it is never reported as zero.
#include <linux/perf_event.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "harness/instruments/instrument.hpp"
#include "harness/instruments/measurements.hpp"

namespace suite {

// The system call (glibc has no wrapper); -1 with errno on failure.
inline int open_event(perf_event_attr* attr, pid_t pid, int cpu, int group_fd) {
    return static_cast<int>(syscall(SYS_perf_event_open, attr, pid, cpu, group_fd, PERF_FLAG_FD_CLOEXEC));
}

// What this process may count, from perf_event_paranoid and its capabilities.
struct PerfAccess {
    int paranoid = 2;         // /proc/sys/kernel/perf_event_paranoid (2 if unreadable: the kernel default)
    bool privileged = false;  // root, CAP_PERFMON or CAP_SYS_ADMIN: paranoid does not apply
    bool user_only() const { return !privileged && paranoid >= 2; }
    bool forbidden() const { return !privileged && paranoid >= 3; }  // Debian's "no perf for users"
    std::string scope() const { return user_only() ? "user" : "user+kernel"; }
};

PerfAccess perf_access();  // of this process

struct CounterSpec {
    std::string name;       // as asked
    std::string canonical;  // libpfm4's fully qualified name
    perf_event_attr attr{};
    bool hardware = false;  // needs a PMU (anything but PERF_TYPE_SOFTWARE)
    // Counted only in kernel mode (context switches, migrations happen in the scheduler): a
    // user-only count would always read 0, so such an event is unavailable under user_only().
    bool kernel_mode_only = false;
};

// The event list of --counters: "default", "none" or names separated by commas. An unknown name
// is a UsageError naming it. "default" keeps the hardware events of the default set that can be
// opened here; the others go to `omitted` with the reason.
struct CounterSelection {
    std::vector<CounterSpec> events;
    std::vector<std::pair<std::string, std::string>> omitted;
    bool requested = false;
};
CounterSelection parse_counters(const std::string& text, const PerfAccess& access);

// Why this process may not count the event at all (paranoid level, kernel-mode-only event, a
// raw event the PMU does not implement), or "".
std::string policy_refusal(const CounterSpec& spec, const PerfAccess& access);
// Why an event cannot be counted by this process, or "" when a trial open succeeds.
std::string probe_event(const CounterSpec& spec, const PerfAccess& access);

// Why the CPU's PMU would count nothing for this raw event although the kernel opens it: an Arm
// PMUv3 common event that its sysfs events/ (under `root`/bus/event_source/devices/armv8_*)
// does not list, i.e. that its PMCEID registers say is not implemented. "" when it is
// implemented or nothing can be known (not an Arm PMU, an implementation-defined number).
std::string unimplemented_event_reason(const perf_event_attr& attr, const std::string& root);
std::string events_sysfs_root();  // SUITE_SYSFS_ROOT if set, else "/sys"

// Names libpfm4 knows on this machine for `./suite list --counters`: every event of every PMU
// it detected, grouped by PMU ("perf" is the kernel's generic set).
struct PmuEvents {
    std::string pmu, description;
    std::vector<std::string> events;
};
std::vector<PmuEvents> known_events();

// A count over an interval in which the event was enabled `enabled` ns and on the PMU `running`
// ns: scaled up by enabled/running when the PMU multiplexed it; nullopt when it never ran.
std::optional<double> scaled_count(std::uint64_t value, std::uint64_t enabled, std::uint64_t running);

// One counter over one repetition on one thread: its value and the ns it was enabled and on the PMU.
struct CountDelta {
    std::uint64_t value = 0, enabled = 0, running = 0;
};
// The team's count of one event over one repetition: each thread's value scaled by its own
// enabled/running, summed. nullopt when a thread's counter was enabled but never on the PMU
// during it (a multiplexed event in a repetition shorter than the kernel's rotation interval):
// that repetition has no count for the event, which is not a count of 0.
std::optional<double> team_count(const std::vector<CountDelta>& per_thread);

// The reason text for a failed perf_event_open; pure, so that tests can check every branch.
std::string open_failure_reason(int err, bool hardware, const PerfAccess& access);

// The counters of one point, opened on every thread of the OpenMP team (each thread opens its
// own, pid 0), the hardware events of a thread in one group so that they are counted over the
// same cycles. Move-only; start()/stop() bracket one repetition exactly where the runner's clock
// does. Empty (default-constructed, --counters=none) it counts nothing: the null object.
class TeamCounters final : public RepetitionInstrument {
public:
    TeamCounters() = default;
    TeamCounters(const std::vector<CounterSpec>& specs, int threads, const PerfAccess& access);
    TeamCounters(TeamCounters&&) noexcept;
    TeamCounters& operator=(TeamCounters&&) noexcept;
    TeamCounters(const TeamCounters&) = delete;
    TeamCounters& operator=(const TeamCounters&) = delete;
    ~TeamCounters() override;

    bool empty() const { return specs_.empty(); }
    void start() override;
    void stop(double seconds) override;  // adds one repetition (the counts need no clock)
    void stop() { stop(0.0); }
    // After the repetitions: were they run by the threads that opened the counters? (OpenMP
    // keeps its pool, but a count that missed work would be a wrong number.)
    void check_team();
    // Summary over the repetitions; `batch` calls per repetition, units and bytes per call.
    CounterReadings readings(int batch, double units, double stream_bytes, int line_bytes) const;

private:
    using Raw = CountDelta;
    void read_all(std::vector<Raw>& into);  // a failed read marks the event lost
    Raw& at(std::vector<Raw>& v, int thread, std::size_t event) const { return v[thread * specs_.size() + event]; }

    std::vector<CounterSpec> specs_;
    PerfAccess access_;
    int threads_ = 0;
    std::vector<int> fds_;              // [thread][event], -1 where it could not be opened
    std::vector<std::string> reasons_;  // [event]: first failure
    std::vector<int> tids_;             // thread ids that opened them
    std::vector<Raw> begin_;
    std::vector<std::vector<double>> reps_;  // [event][repetition]: scaled sum over threads
    std::vector<int> uncounted_;             // [event]: repetitions it was never on the PMU in
    std::vector<Raw> totals_;                // [thread][event]: summed deltas
    std::vector<std::string> lost_;          // [event]: why a repetition could not be counted
    std::string team_changed_;
};

}  // namespace suite
