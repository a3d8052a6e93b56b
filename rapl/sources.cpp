// Where RAPL energy can be read: powercap zones in sysfs, or the perf power PMU.
#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>

#include "harness/instruments/counters.hpp"
#include "harness/common/units.hpp"
#include "rapl/energy.hpp"

namespace fs = std::filesystem;

namespace suite {

namespace {

// The first line of a small sysfs file; false with errno set when it cannot be read.
bool read_line(const std::string& path, std::string& out) {
    const int fd = open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) return false;
    char buf[256];
    const ssize_t n = read(fd, buf, sizeof buf - 1);
    const int err = errno;
    close(fd);
    if (n < 0) {
        errno = err;
        return false;
    }
    out.assign(buf, static_cast<std::size_t>(n));
    if (auto nl = out.find('\n'); nl != std::string::npos) out.resize(nl);
    return true;
}

bool parse_u64(const std::string& text, std::uint64_t& v) {
    if (text.empty() || text.find_first_not_of("0123456789") != std::string::npos) return false;
    errno = 0;
    v = std::strtoull(text.c_str(), nullptr, 10);
    return errno == 0;
}

std::string unreadable_reason(const std::string& path, int err) {
    if (err == EACCES || err == EPERM)
        return path + " is readable only by root (Linux 5.10 and later, CVE-2020-8694); run as root, or: sudo chmod o+r " + path;
    return "cannot read " + path + ": " + std::strerror(err);
}

// powercap names: "package-0" -> package on socket 0; subzones ("core", "dram", ...) inherit the socket.
void name_zone(const std::string& name, std::optional<int> parent_socket, EnergySource& s) {
    static const std::regex package(R"(package-(\d+))");
    std::smatch m;
    if (std::regex_match(name, m, package)) {
        s.domain = "package";
        s.socket = std::stoi(m[1]);
    } else {
        s.domain = name;
        s.socket = name == "psys" ? std::nullopt : parent_socket;
    }
}

}  // namespace

EnergyBackend parse_energy_backend(const std::string& text) {
    if (text == "auto") return EnergyBackend::automatic;
    if (text == "sysfs") return EnergyBackend::sysfs;
    if (text == "perf") return EnergyBackend::perf;
    if (text == "none") return EnergyBackend::none;
    throw UsageError("--energy=" + text + " is not a backend; accepted: auto, sysfs, perf, none");
}

std::string sysfs_root() {
    const char* env = std::getenv("SUITE_SYSFS_ROOT");
    return env && *env ? env : "/sys";
}

std::vector<EnergySource> discover_powercap(const std::string& root, std::string& reason) {
    const fs::path base = fs::path(root) / "class" / "powercap";
    std::error_code ec;
    if (!fs::is_directory(base, ec)) {
        reason = base.string() + " does not exist (no powercap: a virtual machine, or a kernel without it)";
        return {};
    }
    // intel-rapl:0, intel-rapl:0:1, intel-rapl-mmio:0 (AMD's RAPL also appears as intel-rapl).
    static const std::regex zone(R"(([a-z-]*rapl[a-z-]*):(\d+)(?::(\d+))?)");
    std::map<std::string, std::vector<std::string>> by_type;  // control type -> zone directory names
    for (const auto& entry : fs::directory_iterator(base, ec)) {
        const std::string n = entry.path().filename().string();
        std::smatch m;
        if (std::regex_match(n, m, zone)) by_type[m[1]].push_back(n);
    }
    std::vector<EnergySource> out;
    std::vector<std::pair<std::string, std::optional<int>>> seen;  // domain, socket: the MMIO interface repeats the MSR one
    auto order = [](const std::string& a, const std::string& b) {  // intel-rapl:1 before intel-rapl:10, parents first
        auto key = [](const std::string& s) {
            std::vector<int> v;
            for (auto& p : split(s.substr(s.find(':') + 1), ':')) v.push_back(std::stoi(p));
            return v;
        };
        return key(a) < key(b);
    };
    for (const char* type : {"intel-rapl", "amd-rapl", "intel-rapl-mmio"}) {
        auto it = by_type.find(type);
        if (it == by_type.end()) continue;
        std::sort(it->second.begin(), it->second.end(), order);
        std::map<std::string, std::optional<int>> zone_socket;
        for (const auto& z : it->second) {
            const fs::path dir = base / z;
            std::string name;
            if (!read_line((dir / "name").string(), name) || name.empty()) continue;
            std::optional<int> parent;
            if (auto cut = z.rfind(':'); std::count(z.begin(), z.end(), ':') == 2) parent = zone_socket[z.substr(0, cut)];
            EnergySource s;
            name_zone(name, parent, s);
            zone_socket[z] = s.socket;
            if (std::find(seen.begin(), seen.end(), std::make_pair(s.domain, s.socket)) != seen.end()) continue;
            seen.emplace_back(s.domain, s.socket);
            s.where = (dir / "energy_uj").string();
            std::string text;
            if (!read_line((dir / "max_energy_range_uj").string(), text) || !parse_u64(text, s.max_raw)) s.max_raw = 0;
            if (!read_line(s.where, text))
                s.reason = unreadable_reason(s.where, errno);
            else if (std::uint64_t v; !parse_u64(text, v))
                s.reason = s.where + " holds '" + text + "', not a count of microjoules";
            out.push_back(std::move(s));
        }
    }
    if (out.empty()) reason = "no RAPL zone under " + base.string() + " (a virtual machine, or the intel_rapl driver is not loaded)";
    return out;
}

std::vector<EnergySource> discover_perf_power(const std::string& root, std::string& reason) {
    const fs::path dir = fs::path(root) / "bus" / "event_source" / "devices" / "power";
    std::string text;
    std::uint64_t type = 0;
    if (!read_line((dir / "type").string(), text) || !parse_u64(text, type)) {
        reason = "no perf power PMU (" + (dir / "type").string() + " is missing)";
        return {};
    }
    std::vector<int> cpus;
    if (read_line((dir / "cpumask").string(), text) && !text.empty()) cpus = parse_cpu_list(text);
    if (cpus.empty()) cpus = {0};
    static const std::map<std::string, std::string> domains = {
        {"energy-pkg", "package"}, {"energy-cores", "core"}, {"energy-gpu", "uncore"}, {"energy-ram", "dram"}, {"energy-psys", "psys"}};
    std::vector<EnergySource> out;
    for (const auto& [event, domain] : domains) {
        std::string config;
        if (!read_line((dir / "events" / event).string(), config)) continue;
        static const std::regex code(R"(event=(0x[0-9a-fA-F]+|\d+))");
        std::smatch m;
        if (!std::regex_search(config, m, code)) continue;
        double scale = 0;
        if (read_line((dir / "events" / (event + ".scale")).string(), text)) scale = std::strtod(text.c_str(), nullptr);
        std::string unit;
        read_line((dir / "events" / (event + ".unit")).string(), unit);
        const std::size_t count = domain == "psys" ? 1 : cpus.size();
        for (std::size_t i = 0; i < count; ++i) {
            const int cpu = cpus[i];
            EnergySource s;
            s.domain = domain;
            if (domain != "psys") {
                std::string pkg;
                const fs::path p = fs::path(root) / "devices" / "system" / "cpu" / ("cpu" + std::to_string(cpu)) / "topology" / "physical_package_id";
                s.socket = read_line(p.string(), pkg) && !pkg.empty() ? std::stoi(pkg) : static_cast<int>(i);
            }
            s.where = "perf power/" + event + "/ on CPU " + std::to_string(cpu);
            s.joules_per_unit = scale;
            if (scale <= 0 || unit != "Joules") {
                s.reason = "the power PMU gives " + event + " no usable scale and unit (" + std::to_string(scale) + " " + unit + ")";
                out.push_back(std::move(s));
                continue;
            }
            perf_event_attr attr{};
            attr.size = sizeof attr;
            attr.type = static_cast<std::uint32_t>(type);
            attr.config = std::stoull(m[1], nullptr, 0);
            s.fd = open_event(&attr, -1, cpu, -1);
            if (s.fd < 0) {
                const int err = errno;
                s.reason = "cannot open " + s.where + ": " + std::strerror(err) +
                           (err == EACCES || err == EPERM ? " (system-wide events need root, or sudo sysctl kernel.perf_event_paranoid=0)" : "");
            }
            out.push_back(std::move(s));
        }
    }
    if (out.empty()) reason = "the perf power PMU at " + dir.string() + " lists no energy event";
    return out;
}

bool read_raw(const EnergySource& s, std::uint64_t& raw, std::string& error) {
    if (s.fd >= 0) {
        if (read(s.fd, &raw, sizeof raw) == static_cast<ssize_t>(sizeof raw)) return true;
        error = "reading " + s.where + " failed: " + std::strerror(errno);
        return false;
    }
    std::string text;
    if (!read_line(s.where, text)) {
        error = unreadable_reason(s.where, errno);
        return false;
    }
    if (!parse_u64(text, raw)) {
        error = s.where + " holds '" + text + "', not a count";
        return false;
    }
    return true;
}

double joules_between(const EnergySource& s, std::uint64_t begin, std::uint64_t end) {
    std::uint64_t delta = end - begin;  // 64-bit counters (perf) never wrap in practice
    if (end < begin && s.max_raw > 0) delta = (s.max_raw - begin) + end;  // powercap wraps to 0 after max_energy_range_uj
    return static_cast<double>(delta) * s.joules_per_unit;
}

}  // namespace suite
