#pragma once
// What else the machine was doing while a point was timed, and whether that makes the point
// unstable. Read around the timed repetitions (the runner decides when):
//   - the CPU time other tasks took on the team's CPUs: their busy jiffies in /proc/stat less
//     this process's own CPU time (getrusage);
//   - the hypervisor's steal time on those CPUs (/proc/stat, the 8th field);
//   - the time this process's threads waited, runnable, while another task had their CPU (the
//     run-queue delay of /proc/self/task/*/schedstat, in nanoseconds: the precise form of the
//     involuntary context switches, which are recorded too, from getrusage);
//   - the 1-minute load average (/proc/loadavg), recorded for the reader, not judged: it lags.
// A point is flagged unstable when the repetitions' robust spread, the run-queue wait, the steal
// or the others' share passes its threshold, as pyperf warns of an unstable benchmark; `suite
// check` then calls the point inconclusive instead of a pass or a regression. The /proc root is
// injectable so that tests feed fixture files.
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace suite {

struct CpuJiffies {
    std::uint64_t busy = 0;   // user, nice, system, irq, softirq (guest time is inside user)
    std::uint64_t idle = 0;   // idle and iowait
    std::uint64_t steal = 0;  // taken by the hypervisor for other guests
    std::uint64_t total() const { return busy + idle + steal; }
};

struct LoadSnapshot {
    bool have_stat = false;                 // /proc/stat was read and had the CPUs asked for
    CpuJiffies cpus;                        // summed over the CPUs asked for
    double process_cpu_s = 0;               // this process's user + system time
    std::int64_t involuntary_switches = 0;  // this process's, all threads
    std::optional<double> run_delay_s;      // this process's threads, summed: waiting for a CPU
    double wall_s = 0;                      // steady clock
    std::optional<double> load_average;     // 1 minute
};

// Reads PROC/stat (the lines of the given CPUs; all CPUs when `cpus` is empty), PROC/loadavg,
// PROC/self/task/*/schedstat and this process's rusage. Missing or malformed files leave have_stat false or
// load_average empty; it never throws.
LoadSnapshot take_load_snapshot(const std::vector<int>& cpus, const std::string& proc_root = "/proc");

// The thresholds over which a point is unstable. The defaults were set by measurement on the
// 2-core development VM, quiet and with both cores loaded by another process (README, docs/noise.md).
struct StabilityThresholds {
    double spread = 0.10;            // robust relative spread of the repetition times
    double steal = 0.05;             // fraction of the team's CPU time stolen by the hypervisor
    double others = 0.10;            // fraction of the team's CPU time other tasks took
    double waited = 0.05;            // fraction of the window the team's threads waited for a CPU
    std::uint64_t min_jiffies = 10;  // fewer ticks on the team's CPUs than this: too short to judge /proc/stat
};

// Why a point is unstable: which threshold was passed ("other tasks took") and the sentence that
// begins with it and gives the numbers ("other tasks took 48% of the team's CPUs (over 10%)").
struct UnstableReason {
    const char* kind;
    std::string text;
};

struct Stability {
    bool assessed = false;  // false: not judged (under valgrind); nothing below is then measured
    bool unstable = false;
    std::vector<UnstableReason> reasons;    // one for each threshold passed
    double spread = 0;                      // robust relative spread of the samples
    std::optional<double> steal_fraction;   // empty: not judged (window too short, no /proc/stat)
    std::optional<double> others_fraction;  // empty: not judged
    std::optional<double> waited_fraction;  // run-queue wait / (window x threads); empty: no schedstat
    std::int64_t involuntary_switches = 0;
    double window_s = 0;
    std::optional<double> load_average;  // 1 minute, at the end of the window
};

// `ticks_per_s`: the unit of /proc/stat (sysconf(_SC_CLK_TCK), 100 on Linux).
// `threads`: the team's size, over which the run-queue wait is shared.
Stability assess_stability(const LoadSnapshot& before, const LoadSnapshot& after, const std::vector<double>& samples,
                           int threads, const StabilityThresholds& limits = {}, double ticks_per_s = 100);

}  // namespace suite
