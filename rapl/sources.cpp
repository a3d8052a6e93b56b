// Where RAPL energy can be read: powercap zones in sysfs, or the perf power PMU.
#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <climits>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <map>
#include <regex>

#include "harness/common/did_you_mean.hpp"
#include "harness/common/sysfs_file.hpp"
#include "harness/common/text.hpp"
#include "harness/common/units.hpp"
#include "harness/instruments/counters.hpp"
#include "rapl/energy.hpp"

namespace fs = std::filesystem;

namespace suite {

namespace {

// Every file here is read by read_attribute (bounded in time and size), and every number in
// one is checked as strictly as a number typed by the user: what does not fit makes that source
// unavailable with the reason, never the run fail.

// The first line of an attribute file, or false.
bool read_line(const std::string& path, std::string& out) {
    const AttributeText a = read_attribute(path);
    if (a.ok) out = a.text;
    return a.ok;
}

// Text from the system, shown in a message: at most 40 characters.
std::string shown(const std::string& text) {
    return "'" + (text.size() > 40 ? text.substr(0, 40) + "..." : text) + "'";
}

std::string unreadable_reason(const std::string& path, const AttributeText& a) {
    if (a.error == EACCES || a.error == EPERM)
        return path +
               " is readable only by root (Linux 5.10 and later, CVE-2020-8694); run as root, or: sudo chmod o+r " +
               path;
    return a.reason;
}

// powercap names: "package-0" -> package on socket 0; subzones ("core", "dram", ...) inherit the socket.
void name_zone(const std::string& name, std::optional<int> parent_socket, EnergySource& s) {
    static const std::regex package(R"(package-(\d+))");
    std::smatch m;
    if (std::regex_match(name, m, package)) {
        s.domain = "package";
        if (const auto socket = whole_number(m[1].str(), INT_MAX))
            s.socket = static_cast<int>(*socket);
        else
            s.reason = "the zone named " + shown(name) + " gives a socket number above " + std::to_string(INT_MAX) +
                       ", which no socket has; not read";
    } else {
        s.domain = name;
        s.socket = name == "psys" ? std::nullopt : parent_socket;
    }
}

}  // namespace

EnergyBackend parse_energy_backend(const std::string& text) {
    if (const Choice<EnergyChoice>* c = energy_backends().find(text)) return c->what.backend;
    const std::string hint = nearest(text, energy_backends().names());
    throw UsageError("--energy=" + text + " is not a backend; accepted: " + energy_backends().accepted() +
                     (hint.empty() ? "" : " (did you mean '" + hint + "'?)"));
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
    std::vector<std::pair<std::string, std::optional<int>>>
        seen;  // domain, socket: the MMIO interface repeats the MSR one
    // The zone's numbers: intel-rapl:0:1 -> {0, 1}. The kernel numbers zones with an int; a
    // larger number is kept (sorted last) and that zone is refused below.
    auto numbers = [](const std::string& s) {
        std::vector<std::uint64_t> v;
        for (auto& p : split(s.substr(s.find(':') + 1), ':')) v.push_back(whole_number(p).value_or(UINT64_MAX));
        return v;
    };
    auto order = [&](const std::string& a, const std::string& b) {
        return numbers(a) < numbers(b);
    };  // intel-rapl:1 before intel-rapl:10, parents first
    for (const char* type : {"intel-rapl", "amd-rapl", "intel-rapl-mmio"}) {
        auto it = by_type.find(type);
        if (it == by_type.end()) continue;
        std::sort(it->second.begin(), it->second.end(), order);
        std::map<std::string, std::optional<int>> zone_socket;
        for (const auto& z : it->second) {
            const fs::path dir = base / z;
            const AttributeText name_file = read_attribute((dir / "name").string());
            if (!name_file.ok && name_file.error != ENOENT) {  // a zone whose name cannot be read: say so
                EnergySource s;
                s.domain = z;
                s.where = (dir / "energy_uj").string();
                s.reason = name_file.reason;
                out.push_back(std::move(s));
                continue;
            }
            const std::string name = name_file.text;
            if (name.empty()) continue;  // not an energy zone
            std::optional<int> parent;
            if (auto cut = z.rfind(':'); std::count(z.begin(), z.end(), ':') == 2)
                parent = zone_socket[z.substr(0, cut)];
            EnergySource s;
            name_zone(name, parent, s);
            zone_socket[z] = s.socket;
            if (std::find(seen.begin(), seen.end(), std::make_pair(s.domain, s.socket)) != seen.end()) continue;
            seen.emplace_back(s.domain, s.socket);
            s.where = (dir / "energy_uj").string();
            const auto zone_numbers = numbers(z);
            if (std::any_of(zone_numbers.begin(), zone_numbers.end(), [](std::uint64_t n) { return n > INT_MAX; }))
                s.reason = "powercap zone " + z + " has a number above " + std::to_string(INT_MAX) +
                           ", which the kernel never gives a zone; not read";
            if (s.reason.empty()) {
                std::string text;
                s.max_raw =
                    read_line((dir / "max_energy_range_uj").string(), text) ? whole_number(text).value_or(0) : 0;
                const AttributeText e = read_attribute(s.where);
                if (!e.ok)
                    s.reason = unreadable_reason(s.where, e);
                else if (!whole_number(e.text))
                    s.reason = s.where + " holds " + shown(e.text) + ", not a count of microjoules";
            }
            out.push_back(std::move(s));
        }
    }
    if (out.empty())
        reason = "no RAPL zone under " + base.string() + " (a virtual machine, or the intel_rapl driver is not loaded)";
    return out;
}

std::vector<EnergySource> discover_perf_power(const std::string& root, std::string& reason) {
    const fs::path dir = fs::path(root) / "bus" / "event_source" / "devices" / "power";
    std::string text;
    const AttributeText type_file = read_attribute((dir / "type").string());
    if (!type_file.ok) {
        reason = type_file.error == ENOENT ? "no perf power PMU (" + (dir / "type").string() + " is missing)"
                                           : type_file.reason;
        return {};
    }
    const auto type = whole_number(type_file.text, UINT32_MAX);
    if (!type) {
        reason = (dir / "type").string() + " holds " + shown(type_file.text) + ", not a PMU type number";
        return {};
    }
    std::vector<int> cpus;
    if (read_line((dir / "cpumask").string(), text) && !text.empty()) {
        try {
            cpus = parse_cpu_list(text);
        } catch (const UsageError& e) {
            reason = (dir / "cpumask").string() + " is not a CPU list: " + e.what();
            return {};
        }
    }
    if (cpus.empty()) cpus = {0};
    static const std::map<std::string, std::string> domains = {{"energy-pkg", "package"},
                                                               {"energy-cores", "core"},
                                                               {"energy-gpu", "uncore"},
                                                               {"energy-ram", "dram"},
                                                               {"energy-psys", "psys"}};
    std::vector<EnergySource> out;
    for (const auto& [event, domain] : domains) {
        std::string config;
        if (!read_line((dir / "events" / event).string(), config)) continue;
        static const std::regex code(R"(event=(0x[0-9a-fA-F]+|\d+))");
        std::smatch m;
        if (!std::regex_search(config, m, code)) continue;
        std::uint64_t code_value = 0;
        const std::string code_text = m[1].str();
        const bool hex = code_text.rfind("0x", 0) == 0;
        const char* first = code_text.data() + (hex ? 2 : 0);
        const bool code_ok =
            std::from_chars(first, code_text.data() + code_text.size(), code_value, hex ? 16 : 10).ec == std::errc();
        double scale = 0;
        if (read_line((dir / "events" / (event + ".scale")).string(), text)) scale = std::strtod(text.c_str(), nullptr);
        std::string unit;
        read_line((dir / "events" / (event + ".unit")).string(), unit);
        const std::size_t count = domain == "psys" ? 1 : cpus.size();
        for (std::size_t i = 0; i < count; ++i) {
            const int cpu = cpus[i];
            EnergySource s;
            s.domain = domain;
            s.where = "perf power/" + event + "/ on CPU " + std::to_string(cpu);
            if (domain != "psys") {
                // The socket from the CPU's topology; by position when the file is not there.
                const fs::path p = fs::path(root) / "devices" / "system" / "cpu" / ("cpu" + std::to_string(cpu)) /
                                   "topology" / "physical_package_id";
                const AttributeText pkg = read_attribute(p.string());
                const auto socket = pkg.ok ? whole_number(pkg.text, INT_MAX) : std::nullopt;
                if (socket)
                    s.socket = static_cast<int>(*socket);
                else if (!pkg.ok && pkg.error == ENOENT)
                    s.socket = static_cast<int>(i);
                else
                    s.reason =
                        pkg.ok ? p.string() + " holds " + shown(pkg.text) + ", not a package number" : pkg.reason;
            }
            s.joules_per_unit = scale;
            if (s.reason.empty() && (!(scale > 0) || !std::isfinite(scale) || unit != "Joules"))
                s.reason = "the power PMU gives " + event + " no usable scale and unit (" + std::to_string(scale) +
                           " " + unit + ")";
            if (s.reason.empty() && !code_ok)
                s.reason = "the power PMU's " + event + " event code " + shown(code_text) + " is not a 64-bit number";
            if (!s.reason.empty()) {
                out.push_back(std::move(s));
                continue;
            }
            perf_event_attr attr{};
            attr.size = sizeof attr;
            attr.type = static_cast<std::uint32_t>(*type);
            attr.config = code_value;
            s.fd = open_event(&attr, -1, cpu, -1);
            if (s.fd < 0) {
                const int err = errno;
                s.reason = "cannot open " + s.where + ": " + std::strerror(err) +
                           (err == EACCES || err == EPERM
                                ? " (system-wide events need root, or sudo sysctl kernel.perf_event_paranoid=0)"
                                : "");
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
    const AttributeText a = read_attribute(s.where);
    if (!a.ok) {
        error = unreadable_reason(s.where, a);
        return false;
    }
    const auto v = whole_number(a.text);
    if (!v) {
        error = s.where + " holds " + shown(a.text) + ", not a count";
        return false;
    }
    raw = *v;
    return true;
}

double joules_between(const EnergySource& s, std::uint64_t begin, std::uint64_t end) {
    std::uint64_t delta = end - begin;  // 64-bit counters (perf) never wrap in practice
    if (end < begin && s.max_raw > 0)
        delta = (s.max_raw - begin) + end;  // powercap wraps to 0 after max_energy_range_uj
    return static_cast<double>(delta) * s.joules_per_unit;
}

}  // namespace suite
