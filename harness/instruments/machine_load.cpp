#include "harness/instruments/machine_load.hpp"

#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include "harness/common/stats.hpp"

namespace suite {

namespace {

std::string percent(double x) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.0f%%", x * 100);
    return buf;
}

// One "cpuN user nice system idle iowait irq softirq steal ..." line; false if malformed.
bool parse_cpu_line(const std::string& line, int& cpu, CpuJiffies& j) {
    std::istringstream in(line);
    std::string name;
    in >> name;
    if (name.size() <= 3 || name.compare(0, 3, "cpu") != 0) return false;
    try {
        std::size_t used = 0;
        cpu = std::stoi(name.substr(3), &used);
        if (used != name.size() - 3 || cpu < 0) return false;
    } catch (const std::exception&) {
        return false;
    }
    std::uint64_t f[8] = {};
    int fields = 0;
    while (fields < 8 && in >> f[fields]) ++fields;
    if (fields < 7) return false;  // 7: a kernel before 2.6.11, without the steal field (read as 0)
    j.busy = f[0] + f[1] + f[2] + f[5] + f[6];
    j.idle = f[3] + f[4];
    j.steal = f[7];
    return true;
}

}  // namespace

LoadSnapshot take_load_snapshot(const std::vector<int>& cpus, const std::string& proc_root) {
    LoadSnapshot s;
    s.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
    rusage ru{};
    if (getrusage(RUSAGE_SELF, &ru) == 0) {
        s.process_cpu_s = static_cast<double>(ru.ru_utime.tv_sec + ru.ru_stime.tv_sec) +
                          static_cast<double>(ru.ru_utime.tv_usec + ru.ru_stime.tv_usec) * 1e-6;
        s.involuntary_switches = ru.ru_nivcsw;
    }
    const std::set<int> wanted(cpus.begin(), cpus.end());
    std::ifstream stat(proc_root + "/stat");
    std::string line;
    std::set<int> found;
    while (std::getline(stat, line)) {
        if (line.compare(0, 3, "cpu") != 0) break;  // the cpu lines come first
        int cpu = -1;
        CpuJiffies j;
        if (!parse_cpu_line(line, cpu, j)) continue;  // the "cpu " total line, or garbage
        if (!wanted.empty() && !wanted.count(cpu)) continue;
        s.cpus.busy += j.busy;
        s.cpus.idle += j.idle;
        s.cpus.steal += j.steal;
        found.insert(cpu);
    }
    s.have_stat = !found.empty() && (wanted.empty() || found.size() == wanted.size());
    // Each thread's "on-CPU ns, run-queue wait ns, timeslices"; threads come and go, so a thread
    // that ended between two snapshots takes its wait with it (OpenMP keeps its pool).
    std::error_code ec;
    double delay_ns = 0;
    bool any_schedstat = false;
    for (const auto& task : std::filesystem::directory_iterator(proc_root + "/self/task", ec)) {
        std::ifstream in(task.path() / "schedstat");
        double on_cpu = 0, wait = 0;
        if (in >> on_cpu >> wait && std::isfinite(wait) && wait >= 0) {
            delay_ns += wait;
            any_schedstat = true;
        }
    }
    if (any_schedstat) s.run_delay_s = delay_ns * 1e-9;
    std::ifstream loadavg(proc_root + "/loadavg");
    double one = 0;
    if (loadavg >> one && std::isfinite(one) && one >= 0) s.load_average = one;
    return s;
}

Stability assess_stability(const LoadSnapshot& before, const LoadSnapshot& after, const std::vector<double>& samples,
                           int threads, const StabilityThresholds& limits, double ticks_per_s) {
    Stability st;
    st.assessed = true;
    st.spread = robust_relative_spread(samples);
    st.window_s = std::max(0.0, after.wall_s - before.wall_s);
    st.involuntary_switches = std::max<std::int64_t>(0, after.involuntary_switches - before.involuntary_switches);
    st.load_average = after.load_average;
    // The sentence begins with its kind, which the table's summary counts.
    auto flag = [&st](const char* kind, double value, const std::string& of, double limit) {
        st.reasons.push_back({kind, std::string(kind) + " " + percent(value) + of + " (over " + percent(limit) + ")"});
    };
    if (st.spread > limits.spread) flag("the repetitions spread", st.spread, "", limits.spread);
    if (before.have_stat && after.have_stat && after.cpus.total() >= before.cpus.total() &&
        after.cpus.total() - before.cpus.total() >= limits.min_jiffies) {
        const double total = static_cast<double>(after.cpus.total() - before.cpus.total());
        const double steal = static_cast<double>(after.cpus.steal - std::min(after.cpus.steal, before.cpus.steal));
        const double busy = static_cast<double>(after.cpus.busy - std::min(after.cpus.busy, before.cpus.busy));
        const double ours = std::max(0.0, after.process_cpu_s - before.process_cpu_s) * ticks_per_s;
        st.steal_fraction = steal / total;
        st.others_fraction = std::clamp((busy - ours) / total, 0.0, 1.0);
        if (*st.steal_fraction > limits.steal)
            flag("the hypervisor stole", *st.steal_fraction, " of the team's CPU time", limits.steal);
        if (*st.others_fraction > limits.others)
            flag("other tasks took", *st.others_fraction, " of the team's CPUs", limits.others);
    }
    if (st.window_s > 0 && threads > 0 && before.run_delay_s && after.run_delay_s) {
        st.waited_fraction = std::max(0.0, *after.run_delay_s - *before.run_delay_s) / (st.window_s * threads);
        if (*st.waited_fraction > limits.waited)
            flag("the team waited for a CPU", *st.waited_fraction, " of the time", limits.waited);
    }
    st.unstable = !st.reasons.empty();
    return st;
}

}  // namespace suite
