// Counters opened by each thread of the OpenMP team for itself, read around each repetition.
// Reading running counters (rather than enabling and disabling them) keeps start and stop to one
// read per counter, and the time-enabled/time-running pair of each read scales what a
// multiplexed counter missed.
#include <omp.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <utility>

#include "harness/common/stats.hpp"
#include "harness/instruments/counters.hpp"

namespace suite {

namespace {

int this_tid() { return static_cast<int>(syscall(SYS_gettid)); }

constexpr const char* kCycles = "perf::PERF_COUNT_HW_CPU_CYCLES";
constexpr const char* kInstructions = "perf::PERF_COUNT_HW_INSTRUCTIONS";
constexpr const char* kLlcLoadMisses = "perf::PERF_COUNT_HW_CACHE_LL:READ:MISS";
constexpr const char* kCacheMisses = "perf::PERF_COUNT_HW_CACHE_MISSES";

}  // namespace

TeamCounters::TeamCounters(const std::vector<CounterSpec>& specs, int threads, const PerfAccess& access)
    : specs_(specs), access_(access), threads_(threads) {
    const std::size_t n = specs_.size();
    fds_.assign(static_cast<std::size_t>(threads) * n, -1);
    reasons_.assign(n, "");
    lost_.assign(n, "");
    reps_.assign(n, {});
    uncounted_.assign(n, 0);
    totals_.assign(static_cast<std::size_t>(threads) * n, Raw{});
    tids_.assign(threads, 0);
    for (std::size_t e = 0; e < n; ++e) reasons_[e] = policy_refusal(specs_[e], access_);
    std::vector<int> errs(fds_.size(), 0);
#pragma omp parallel num_threads(threads)
    {
        const int t = omp_get_thread_num();
        tids_[t] = this_tid();
        int leader = -1;  // the first hardware event of this thread leads its group
        for (std::size_t e = 0; e < n; ++e) {
            if (!reasons_[e].empty()) continue;
            perf_event_attr attr = specs_[e].attr;
            attr.read_format = PERF_FORMAT_TOTAL_TIME_ENABLED | PERF_FORMAT_TOTAL_TIME_RUNNING;
            attr.disabled = 0;
            attr.inherit = 0;
            const bool join = specs_[e].hardware && leader >= 0;
            int fd = open_event(&attr, 0, -1, join ? leader : -1);
            if (fd < 0 && join) fd = open_event(&attr, 0, -1, -1);  // the PMU would not take it in the group
            if (fd < 0) {
                errs[t * n + e] = errno;
                continue;
            }
            fds_[t * n + e] = fd;
            if (specs_[e].hardware && leader < 0) leader = fd;
        }
    }
    for (std::size_t e = 0; e < n; ++e) {
        for (int t = 0; t < threads && reasons_[e].empty(); ++t)
            if (const int err = errs[t * n + e]; err != 0)
                reasons_[e] = open_failure_reason(err, specs_[e].hardware, access_) +
                              (t > 0 ? " (on thread " + std::to_string(t) + "; thread 0 could open it)" : "");
        if (reasons_[e].empty()) continue;
        for (int t = 0; t < threads; ++t) {  // all threads or none: a partial sum would be a wrong total
            int& fd = fds_[t * n + e];
            if (fd >= 0) close(fd);
            fd = -1;
        }
    }
    begin_.assign(fds_.size(), Raw{});
}

TeamCounters::TeamCounters(TeamCounters&& o) noexcept { *this = std::move(o); }

TeamCounters& TeamCounters::operator=(TeamCounters&& o) noexcept {
    if (this != &o) {
        std::swap(specs_, o.specs_);
        std::swap(access_, o.access_);
        std::swap(threads_, o.threads_);
        std::swap(fds_, o.fds_);
        std::swap(reasons_, o.reasons_);
        std::swap(tids_, o.tids_);
        std::swap(begin_, o.begin_);
        std::swap(reps_, o.reps_);
        std::swap(uncounted_, o.uncounted_);
        std::swap(totals_, o.totals_);
        std::swap(lost_, o.lost_);
        std::swap(team_changed_, o.team_changed_);
    }
    return *this;
}

TeamCounters::~TeamCounters() {
    for (int fd : fds_)
        if (fd >= 0) close(fd);
}

void TeamCounters::read_all(std::vector<Raw>& into) {
    const std::size_t n = specs_.size();
    for (std::size_t i = 0; i < fds_.size(); ++i) {
        if (fds_[i] < 0) continue;
        std::uint64_t buf[3];
        if (read(fds_[i], buf, sizeof buf) != static_cast<ssize_t>(sizeof buf)) {
            std::string& lost = lost_[i % n];
            if (lost.empty()) lost = std::string("reading the counter failed during the run: ") + std::strerror(errno);
            continue;
        }
        into[i] = Raw{buf[0], buf[1], buf[2]};
    }
}

void TeamCounters::start() {
    if (!empty()) read_all(begin_);
}

void TeamCounters::stop(double) {
    if (empty()) return;
    std::vector<Raw> end(fds_.size());
    read_all(end);
    const std::size_t n = specs_.size();
    std::vector<CountDelta> deltas(threads_);
    for (std::size_t e = 0; e < n; ++e) {
        if (!reasons_[e].empty() || !lost_[e].empty()) continue;
        for (int t = 0; t < threads_; ++t) {
            const Raw& b = begin_[t * n + e];
            const Raw& a = end[t * n + e];
            deltas[t] = Raw{a.value - b.value, a.enabled - b.enabled, a.running - b.running};
            Raw& tot = totals_[t * n + e];  // every repetition, counted or not: the running fraction
            tot.value += deltas[t].value;
            tot.enabled += deltas[t].enabled;
            tot.running += deltas[t].running;
        }
        if (const std::optional<double> sum = team_count(deltas))
            reps_[e].push_back(*sum);
        else
            ++uncounted_[e];
    }
}

void TeamCounters::check_team() {
    if (empty()) return;
    std::vector<int> now(threads_, 0);
#pragma omp parallel num_threads(threads_)
    now[omp_get_thread_num()] = this_tid();
    if (now != tids_) team_changed_ = "the repetitions ran on other OpenMP threads than those that opened the counters";
}

CounterReadings TeamCounters::readings(int batch, double units, double stream_bytes, int line_bytes) const {
    CounterReadings out;
    out.requested = true;
    out.scope = access_.scope();
    const std::size_t n = specs_.size();
    for (std::size_t e = 0; e < n; ++e) {
        EventReading r;
        r.name = specs_[e].name;
        r.canonical = specs_[e].canonical;
        r.hardware = specs_[e].hardware;
        r.reason = !reasons_[e].empty() ? reasons_[e] : !lost_[e].empty() ? lost_[e] : team_changed_;
        if (r.reason.empty() && reps_[e].empty())
            r.reason = uncounted_[e] > 0 ? "never on the PMU during a repetition (more events than the PMU has "
                                           "counters, each repetition shorter than the kernel's rotation; ask for "
                                           "fewer events or lengthen the repetitions)"
                                         : "no repetition was counted";
        r.available = r.reason.empty();
        if (r.available) {
            std::vector<double> per_call;
            for (double v : reps_[e]) per_call.push_back(v / batch);
            const TimeStats s = summarise(per_call);
            r.per_call = {s.median, s.min, s.max};
            if (units > 0) r.per_element = s.median / units;
            if (stream_bytes > 0) r.per_byte = s.median / stream_bytes;
            double enabled = 0, running = 0;
            for (int t = 0; t < threads_; ++t) {
                enabled += static_cast<double>(totals_[t * n + e].enabled);
                running += static_cast<double>(totals_[t * n + e].running);
                r.multiplexed = r.multiplexed || totals_[t * n + e].running < totals_[t * n + e].enabled;
            }
            if (enabled > 0) r.running_fraction = running / enabled;
            r.repetitions_counted = static_cast<int>(reps_[e].size());
            r.repetitions_not_counted = uncounted_[e];
            out.available = true;
        }
        out.events.push_back(std::move(r));
    }
    if (!out.available) out.reason = n == 0 ? "no event could be opened here" : "none of the events could be counted";
    auto find = [&](const char* canonical) -> const EventReading* {
        for (const auto& r : out.events)
            if (r.available && r.canonical == canonical) return &r;
        return nullptr;
    };
    if (const auto* cyc = find(kCycles), *ins = find(kInstructions); cyc && ins && cyc->per_call.median > 0)
        out.ipc = ins->per_call.median / cyc->per_call.median;
    const EventReading* llc = find(kLlcLoadMisses);
    if (!llc) llc = find(kCacheMisses);
    if (llc && line_bytes > 0) {
        out.llc_miss_event = llc->name;
        out.llc_miss_bytes_per_call = llc->per_call.median * line_bytes;
        if (stream_bytes > 0) out.llc_miss_bytes_over_stream_bytes = *out.llc_miss_bytes_per_call / stream_bytes;
    }
    return out;
}

}  // namespace suite
