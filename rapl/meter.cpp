// The energy meter: one reading of every domain at the start and the stop of each repetition.
#include <unistd.h>

#include <chrono>
#include <thread>
#include <utility>

#include "harness/common/stats.hpp"
#include "rapl/energy.hpp"

namespace suite {

namespace {

std::string describe(const EnergySource& s) {
    return s.domain + (s.socket ? " (socket " + std::to_string(*s.socket) + ")" : "");
}

// What a counter that never moved read, every time.
std::string stuck_at(const EnergySource& s, std::uint64_t value) {
    const std::string read = s.where + " read " + std::to_string(value) + (s.fd < 0 ? " µJ" : "") + " every time";
    if (s.max_raw > 0 && value == s.max_raw)
        return read + ", the counter's maximum (max_energy_range_uj): it is stuck there, not counting";
    if (value == 0) return read + " (a virtual machine passes no energy through)";
    return read;
}

}  // namespace

EnergyMeter EnergyMeter::open(EnergyBackend backend, const std::string& root) {
    EnergyMeter m;
    if (backend == EnergyBackend::none) return m;
    m.requested_ = true;
    std::string sysfs_reason, perf_reason;
    auto usable = [](const std::vector<EnergySource>& v) {
        for (const auto& s : v)
            if (s.reason.empty()) return true;
        return false;
    };
    auto first_reason = [](const std::vector<EnergySource>& v, std::string& reason) {
        if (reason.empty() && !v.empty()) reason = v.front().reason;
    };
    if (backend == EnergyBackend::sysfs || backend == EnergyBackend::automatic) {
        m.sources_ = discover_powercap(root, sysfs_reason);
        m.backend_ = energy_backend_name(EnergyBackend::sysfs);
        if (usable(m.sources_)) return m;
        first_reason(m.sources_, sysfs_reason);
    }
    if (backend == EnergyBackend::perf || backend == EnergyBackend::automatic) {
        for (auto& s : m.sources_)
            if (s.fd >= 0) close(s.fd);
        m.sources_ = discover_perf_power(root, perf_reason);
        m.backend_ = energy_backend_name(EnergyBackend::perf);
        if (usable(m.sources_)) return m;
        first_reason(m.sources_, perf_reason);
    }
    for (auto& s : m.sources_)
        if (s.fd >= 0) close(s.fd);
    m.sources_.clear();
    m.backend_.clear();
    if (backend == EnergyBackend::sysfs)
        m.reason_ = sysfs_reason;
    else if (backend == EnergyBackend::perf)
        m.reason_ = perf_reason;
    else
        m.reason_ = "powercap sysfs: " + sysfs_reason + "; perf power PMU: " + perf_reason;
#if !defined(__x86_64__) && !defined(__i386__)
    // What is read is the x86 interface (an injected root is read all the same, for the tests).
    m.reason_ += " (RAPL is Intel's and AMD's x86-64 interface; Arm servers have none)";
#endif
    return m;
}

EnergyMeter::EnergyMeter(EnergyMeter&& o) noexcept { *this = std::move(o); }

EnergyMeter& EnergyMeter::operator=(EnergyMeter&& o) noexcept {
    if (this != &o) {
        std::swap(requested_, o.requested_);
        std::swap(reason_, o.reason_);
        std::swap(backend_, o.backend_);
        std::swap(sources_, o.sources_);
        std::swap(begin_, o.begin_);
        std::swap(joules_, o.joules_);
        std::swap(seconds_, o.seconds_);
        std::swap(advanced_, o.advanced_);
        std::swap(last_, o.last_);
        std::swap(lost_, o.lost_);
        std::swap(idle_watts_, o.idle_watts_);
    }
    return *this;
}

std::vector<EnergyDomainInfo> EnergyMeter::domains() const {
    std::vector<EnergyDomainInfo> out;
    for (const auto& s : sources_) out.push_back({s.domain, s.socket, s.where, s.reason});
    return out;
}

std::unique_ptr<EnergyInstrument> open_energy(const std::string& option) {
    const EnergyBackend backend = parse_energy_backend(option);
    return std::make_unique<EnergyMeter>(EnergyMeter::open(backend, sysfs_root()));
}

EnergyMeter::~EnergyMeter() {
    for (auto& s : sources_)
        if (s.fd >= 0) close(s.fd);
}

void EnergyMeter::start() {
    if (!available()) return;
    const std::size_t n = sources_.size();
    if (joules_.size() != n) {
        joules_.assign(n, {});
        advanced_.assign(n, 0);
        last_.assign(n, 0);
        lost_.assign(n, "");
        idle_watts_.resize(n);
    }
    begin_.assign(n, 0);
    for (std::size_t i = 0; i < n; ++i) {
        if (!sources_[i].reason.empty() || !lost_[i].empty()) continue;
        std::string error;
        if (!read_raw(sources_[i], begin_[i], error)) lost_[i] = "during the run: " + error;
    }
}

void EnergyMeter::stop(double seconds) {
    if (!available()) return;
    seconds_.push_back(seconds);
    for (std::size_t i = 0; i < sources_.size(); ++i) {
        if (!sources_[i].reason.empty() || !lost_[i].empty()) continue;
        std::uint64_t end = 0;
        std::string error;
        if (!read_raw(sources_[i], end, error)) {
            lost_[i] = "during the run: " + error;
            continue;
        }
        const double j = joules_between(sources_[i], begin_[i], end);
        advanced_[i] += end != begin_[i];
        last_[i] = end;
        joules_[i].push_back(j);
    }
}

EnergyReadings EnergyMeter::take(int batch, double units, double stream_bytes, double median_seconds_per_call) {
    EnergyReadings out;
    out.requested = requested_;
    out.backend = backend_;
    if (!available()) {
        out.reason = reason_.empty() ? "energy was not requested" : reason_;
        return out;
    }
    for (std::size_t i = 0; i < sources_.size(); ++i) {
        const EnergySource& s = sources_[i];
        DomainEnergy d;
        d.domain = s.domain;
        d.socket = s.socket;
        const std::vector<double> reps = i < joules_.size() ? joules_[i] : std::vector<double>{};
        if (!s.reason.empty())
            d.reason = s.reason;
        else if (i < lost_.size() && !lost_[i].empty())
            d.reason = lost_[i];
        else if (reps.empty())
            d.reason = "no repetition was measured";
        else if (advanced_[i] == 0)
            d.reason = "the " + describe(s) + " counter did not advance over " + std::to_string(reps.size()) +
                       " repetitions: " + stuck_at(s, last_[i]);
        d.available = d.reason.empty();
        if (d.available) {
            std::vector<double> per_call, watts;
            for (std::size_t r = 0; r < reps.size(); ++r) {
                per_call.push_back(reps[r] / batch);
                d.joules_total += reps[r];
                if (r < seconds_.size() && seconds_[r] > 0) watts.push_back(reps[r] / seconds_[r]);
            }
            const TimeStats st = summarise(per_call);
            d.joules_per_call = {st.median, st.min, st.max};
            if (!watts.empty()) d.watts_median = summarise(watts).median;
            if (stream_bytes > 0) d.nj_per_byte = st.median / stream_bytes * 1e9;
            if (units > 0) d.nj_per_element = st.median / units * 1e9;
            if (i < idle_watts_.size() && idle_watts_[i]) {
                d.idle_watts = idle_watts_[i];
                d.joules_above_idle_per_call = st.median - *idle_watts_[i] * median_seconds_per_call;
            }
            out.available = true;
        }
        out.domains.push_back(std::move(d));
    }
    if (!out.available) out.reason = "no domain could be measured during this point";
    // Forget this point; a source lost in it is tried again at the next.
    for (auto& v : joules_) v.clear();
    seconds_.clear();
    std::fill(advanced_.begin(), advanced_.end(), 0);
    std::fill(lost_.begin(), lost_.end(), "");
    return out;
}

void EnergyMeter::measure_idle(double seconds) {
    if (!available()) return;
    start();
    const auto t0 = std::chrono::steady_clock::now();
    std::this_thread::sleep_for(std::chrono::duration<double>(seconds));
    stop(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    for (std::size_t i = 0; i < sources_.size(); ++i)
        if (!joules_[i].empty() && advanced_[i] > 0 && seconds_[0] > 0) idle_watts_[i] = joules_[i][0] / seconds_[0];
    for (auto& v : joules_) v.clear();
    seconds_.clear();
    std::fill(advanced_.begin(), advanced_.end(), 0);
    std::fill(lost_.begin(), lost_.end(), "");
}

}  // namespace suite
