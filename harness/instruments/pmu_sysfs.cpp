// Which raw events the CPU's PMU implements, as the kernel shows them in sysfs. An Arm PMUv3
// accepts any event number (perf_event_open succeeds), but one its PMCEID registers do not
// announce counts nothing: without this check such an event would be reported as 0.
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <set>
#include <string>

#include "harness/common/sysfs_file.hpp"
#include "harness/common/text.hpp"
#include "harness/instruments/counters.hpp"

namespace suite {

namespace fs = std::filesystem;

namespace {

// "event=0x0008" (possibly with more terms after a comma) -> 8; -1 when there is no event term.
long event_number(const std::string& text) {
    for (const auto& term : split(text, ',')) {
        if (term.rfind("event=", 0) != 0) continue;
        char* end = nullptr;
        const long v = std::strtol(term.c_str() + 6, &end, 0);
        if (end && *end == '\0') return v;
    }
    return -1;
}

// PMUv3 common events (architected numbers) are the ones the PMCEID registers describe; the
// kernel lists them in sysfs only where the PMU implements them. Implementation-defined numbers
// are never listed there, so their absence says nothing.
bool is_common_event(std::uint64_t number) { return number < 0x40 || (number >= 0x4000 && number < 0x4040); }

}  // namespace

std::string events_sysfs_root() {
    const char* env = std::getenv("SUITE_SYSFS_ROOT");  // as rapl/ reads it: one root for every sysfs read
    return env && *env ? env : "/sys";
}

std::string unimplemented_event_reason(const perf_event_attr& attr, const std::string& root) {
    const fs::path devices = fs::path(root) / "bus" / "event_source" / "devices";
    std::error_code ec;
    if (!fs::is_directory(devices, ec)) return "";
    const std::uint64_t number = attr.config & 0xffff;
    bool raw_target = false;
    std::string first_pmu;
    std::set<std::string> names;
    for (const auto& dev : fs::directory_iterator(devices, ec)) {
        const std::string pmu = dev.path().filename().string();
        if (pmu.rfind("armv8_", 0) != 0) continue;  // the Arm CPU PMUs (armv8_pmuv3, armv8_neoverse_n1, ...)
        const AttributeText type = read_attribute((dev.path() / "type").string());
        const bool target = attr.type == PERF_TYPE_RAW || (type.ok && type.text == std::to_string(attr.type));
        if (!target || !fs::is_directory(dev.path() / "events", ec)) continue;
        raw_target = true;
        if (first_pmu.empty()) first_pmu = pmu;
        for (const auto& ev : fs::directory_iterator(dev.path() / "events", ec)) {
            const AttributeText text = read_attribute(ev.path().string());
            if (!text.ok) continue;
            if (event_number(text.text) == static_cast<long>(number)) return "";  // implemented
            names.insert(ev.path().filename().string());
        }
    }
    if (!raw_target || !is_common_event(number) || names.empty()) return "";
    char hex[16];
    std::snprintf(hex, sizeof hex, "0x%02llx", static_cast<unsigned long long>(number));
    std::string have;
    for (const auto& n : names) have += (have.empty() ? "" : ", ") + n;
    return std::string("the CPU's PMU (") + first_pmu + ") does not implement event " + hex + ": " +
           (fs::path(root) / "bus/event_source/devices" / first_pmu / "events").string() +
           " does not list it (the kernel lists the common events the PMU's PMCEID registers announce), so it "
           "would count nothing; this PMU has " +
           have;
}

}  // namespace suite
