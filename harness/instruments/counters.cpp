// Event names to perf_event_attr through libpfm4, what this process may count, and why an
// event cannot be counted. Opening and reading for a team is in team_counters.cpp.
#include "harness/instruments/counters.hpp"

#include <perfmon/pfmlib_perf_event.h>
#include <unistd.h>

#include <cerrno>
#include <charconv>
#include <cstring>
#include <fstream>
#include <mutex>
#include <sstream>

#include "harness/common/sysfs_file.hpp"
#include "harness/common/text.hpp"
#include "harness/common/units.hpp"

namespace suite {

namespace {

void init_libpfm() {
    static std::once_flag once;
    static int status = PFM_SUCCESS;
    std::call_once(once, [] { status = pfm_initialize(); });
    if (status != PFM_SUCCESS)
        throw std::runtime_error(std::string("libpfm4 failed to initialise: ") + pfm_strerror(status));
}

// The default set, close to the thesis's figures: cycles, instructions, L1D and LLC misses, bus
// cycles, and the software events that show whether the run was undisturbed.
const char* const kDefaultHardware[] = {"cycles", "instructions", "L1-dcache-load-misses", "LLC-load-misses",
                                        "bus-cycles"};
const char* const kDefaultSoftware[] = {"task-clock", "page-faults", "context-switches", "cpu-migrations"};

std::vector<std::string> present_pmus() {
    std::vector<std::string> names;
    for (int p = PFM_PMU_NONE; p < PFM_PMU_MAX; ++p) {
        pfm_pmu_info_t info{};
        info.size = sizeof info;
        if (pfm_get_pmu_info(static_cast<pfm_pmu_t>(p), &info) == PFM_SUCCESS && info.is_present)
            names.emplace_back(info.name);
    }
    return names;
}

bool is_kernel_mode_only(const std::string& canonical) {
    return canonical.find("PERF_COUNT_SW_CONTEXT_SWITCHES") != std::string::npos ||
           canonical.find("PERF_COUNT_SW_CPU_MIGRATIONS") != std::string::npos;
}

// One name to a spec; throws UsageError when libpfm4 does not know it.
CounterSpec resolve(const std::string& name, const PerfAccess& access) {
    init_libpfm();
    CounterSpec spec;
    spec.name = name;
    pfm_perf_encode_arg_t arg{};
    arg.attr = &spec.attr;
    arg.size = sizeof arg;
    char* fstr = nullptr;
    arg.fstr = &fstr;
    const int plm = access.user_only() ? PFM_PLM3 : (PFM_PLM0 | PFM_PLM3);
    const int rc = pfm_get_os_event_encoding(name.c_str(), plm, PFM_OS_PERF_EVENT_EXT, &arg);
    if (rc != PFM_SUCCESS) {
        std::string pmus = join(present_pmus(), ", ");
        throw UsageError("unknown counter event '" + name + "' (libpfm4: " + pfm_strerror(rc) +
                         "; PMUs it detected here: " + pmus +
                         "); accepted: default, none, or names from ./suite list --counters");
    }
    spec.canonical = fstr ? fstr : name;
    std::free(fstr);
    // Keep the qualifier-free name: "perf::PERF_COUNT_HW_CPU_CYCLES:u=1:k=1:..." -> "perf::PERF_COUNT_HW_CPU_CYCLES".
    if (auto q = spec.canonical.find(":u="); q != std::string::npos) spec.canonical.resize(q);
    spec.attr.size = sizeof(perf_event_attr);
    spec.hardware = spec.attr.type != PERF_TYPE_SOFTWARE;
    spec.kernel_mode_only = is_kernel_mode_only(spec.canonical);
    return spec;
}

bool running_under_hypervisor() {
    std::ifstream in("/proc/cpuinfo");
    std::string line;
    while (std::getline(in, line))
        if (line.rfind("flags", 0) == 0) return line.find(" hypervisor") != std::string::npos;
    return false;
}

}  // namespace

std::optional<double> scaled_count(std::uint64_t value, std::uint64_t enabled, std::uint64_t running) {
    if (running == 0) {
        if (enabled > 0) return std::nullopt;  // enabled but never scheduled: nothing was counted
        return static_cast<double>(value);     // no time passed at all
    }
    if (running >= enabled) return static_cast<double>(value);
    return static_cast<double>(value) * static_cast<double>(enabled) / static_cast<double>(running);
}

std::optional<double> team_count(const std::vector<CountDelta>& per_thread) {
    double sum = 0;
    for (const CountDelta& d : per_thread) {
        const std::optional<double> v = scaled_count(d.value, d.enabled, d.running);
        if (!v) return std::nullopt;
        sum += *v;
    }
    return sum;
}

PerfAccess perf_access() {
    PerfAccess a;
    // A whole int (-1 and up); anything else leaves the default, the kernel's own.
    if (const AttributeText p = read_attribute("/proc/sys/kernel/perf_event_paranoid"); p.ok) {
        int v = 0;
        const char* end = p.text.data() + p.text.size();
        if (const auto r = std::from_chars(p.text.data(), end, v); r.ec == std::errc() && r.ptr == end) a.paranoid = v;
    }
    // Effective capabilities: CAP_SYS_ADMIN is bit 21, CAP_PERFMON bit 38.
    std::ifstream status("/proc/self/status");
    std::string line;
    bool seen = false;
    while (std::getline(status, line)) {
        if (line.rfind("CapEff:", 0) != 0) continue;
        const std::size_t at = line.find_first_not_of(" \t", 7);
        unsigned long long caps = 0;
        if (at == std::string::npos ||
            std::from_chars(line.data() + at, line.data() + line.size(), caps, 16).ec != std::errc())
            break;
        a.privileged = (caps >> 21 & 1) || (caps >> 38 & 1);
        seen = true;
    }
    if (!seen) a.privileged = geteuid() == 0;
    return a;
}

std::string open_failure_reason(int err, bool hardware, const PerfAccess& access) {
    const std::string sys = std::string("perf_event_open: ") + std::strerror(err);
    if (err == EACCES || err == EPERM) {
        if (access.forbidden())
            return "kernel.perf_event_paranoid is " + std::to_string(access.paranoid) +
                   ", which forbids perf_event_open to unprivileged users; run as root, or set it to 2 (user-mode "
                   "counts) or 1 "
                   "(sudo sysctl kernel.perf_event_paranoid=1) (" +
                   sys + ")";
        return "not permitted with kernel.perf_event_paranoid=" + std::to_string(access.paranoid) +
               "; run as root or set it lower (sudo sysctl kernel.perf_event_paranoid=1) (" + sys + ")";
    }
    if (hardware && (err == ENOENT || err == EOPNOTSUPP || err == ENODEV))
        return std::string("no hardware PMU offers this event to this process") +
               (running_under_hypervisor() ? " (a virtual machine without a virtual PMU)" : "") + " (" + sys + ")";
    if (err == EMFILE) return "too many open files for one counter per event and thread; raise ulimit -n (" + sys + ")";
    if (err == EINVAL) return "the kernel rejected the event's encoding (" + sys + ")";
    return sys;
}

std::string policy_refusal(const CounterSpec& spec, const PerfAccess& access) {
    if (access.forbidden()) return open_failure_reason(EACCES, spec.hardware, access);
    if (spec.kernel_mode_only && access.user_only())
        return "it happens in kernel mode, which kernel.perf_event_paranoid=" + std::to_string(access.paranoid) +
               " keeps unprivileged users from counting (a user-only count would always read 0); run as root or "
               "sudo sysctl kernel.perf_event_paranoid=1";
    if (spec.hardware) return unimplemented_event_reason(spec.attr, events_sysfs_root());
    return "";
}

std::string probe_event(const CounterSpec& spec, const PerfAccess& access) {
    if (std::string why = policy_refusal(spec, access); !why.empty()) return why;
    perf_event_attr attr = spec.attr;
    attr.disabled = 1;
    const long fd = open_event(&attr, 0, -1, -1);
    if (fd < 0) return open_failure_reason(errno, spec.hardware, access);
    close(static_cast<int>(fd));
    return "";
}

CounterSelection parse_counters(const std::string& text, const PerfAccess& access) {
    CounterSelection sel;
    if (text == "none") return sel;
    sel.requested = true;
    if (text.empty() || text == "default") {
        for (const char* name : kDefaultHardware) {
            CounterSpec spec = resolve(name, access);
            if (std::string why = probe_event(spec, access); why.empty())
                sel.events.push_back(spec);
            else
                sel.omitted.emplace_back(name, why);
        }
        for (const char* name : kDefaultSoftware) {
            CounterSpec spec = resolve(name, access);
            if (std::string why = probe_event(spec, access); why.empty() || !spec.kernel_mode_only)
                sel.events.push_back(spec);  // an unopenable software event stays, with its reason
            else
                sel.omitted.emplace_back(name, why);
        }
        return sel;
    }
    for (const auto& name : split(text, ',')) {
        if (name.empty())
            throw UsageError("--counters=" + text +
                             " has an empty event name; accepted: default, none, or NAME,NAME,...");
        if (name == "default" || name == "none")
            throw UsageError("--counters=" + text + ": '" + name + "' cannot be combined with event names");
        for (const auto& have : sel.events)
            if (have.name == name) throw UsageError("--counters=" + text + " names '" + name + "' twice");
        sel.events.push_back(resolve(name, access));
    }
    return sel;
}

std::vector<PmuEvents> known_events() {
    init_libpfm();
    std::vector<PmuEvents> out;
    for (int p = PFM_PMU_NONE; p < PFM_PMU_MAX; ++p) {
        pfm_pmu_info_t info{};
        info.size = sizeof info;
        if (pfm_get_pmu_info(static_cast<pfm_pmu_t>(p), &info) != PFM_SUCCESS || !info.is_present) continue;
        PmuEvents pmu{info.name, info.desc ? info.desc : "", {}};
        for (int e = info.first_event; e != -1; e = pfm_get_event_next(e)) {
            pfm_event_info_t ev{};
            ev.size = sizeof ev;
            if (pfm_get_event_info(e, PFM_OS_NONE, &ev) == PFM_SUCCESS) pmu.events.emplace_back(ev.name);
        }
        out.push_back(std::move(pmu));
    }
    return out;
}

}  // namespace suite
