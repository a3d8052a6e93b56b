#include "harness/cli_counters.hpp"

#include <cstdio>
#include <iostream>

#include <nlohmann/json.hpp>

#include "harness/counters.hpp"

namespace suite {

namespace {

// The names perf(1) users know, each tried here.
const char* const kGeneric[] = {"cycles", "instructions", "cache-references", "cache-misses", "branches", "branch-misses",
                                "bus-cycles", "L1-dcache-loads", "L1-dcache-load-misses", "LLC-loads", "LLC-load-misses",
                                "LLC-store-misses", "dTLB-load-misses", "task-clock", "page-faults", "minor-faults",
                                "major-faults", "context-switches", "cpu-migrations"};

}  // namespace

int list_counters(bool json) {
    const PerfAccess access = perf_access();
    nlohmann::json generic = nlohmann::json::array();
    for (const char* name : kGeneric) {
        CounterSpec spec = parse_counters(name, access).events.front();
        const std::string why = probe_event(spec, access);
        generic.push_back({{"name", name}, {"canonical", spec.canonical}, {"hardware", spec.hardware}, {"available", why.empty()},
                           {"reason", why.empty() ? nlohmann::json(nullptr) : nlohmann::json(why)}});
    }
    const auto pmus = known_events();
    if (json) {
        nlohmann::json p = nlohmann::json::array();
        for (const auto& pmu : pmus) p.push_back({{"pmu", pmu.pmu}, {"description", pmu.description}, {"events", pmu.events}});
        std::cout << nlohmann::json{{"scope", access.scope()}, {"perf_event_paranoid", access.paranoid}, {"privileged", access.privileged},
                                    {"generic", generic}, {"pmus", p}}
                         .dump(2)
                  << "\n";
        return 0;
    }
    std::printf("Counting scope here: %s (perf_event_paranoid=%d, %s)\n\n", access.scope().c_str(), access.paranoid,
                access.privileged ? "privileged" : "unprivileged");
    std::printf("%-24s %-9s %s\n", "event", "kind", "counted here?");
    for (const auto& g : generic)
        std::printf("%-24s %-9s %s\n", g["name"].get<std::string>().c_str(), g["hardware"].get<bool>() ? "hardware" : "software",
                    g["available"].get<bool>() ? "yes" : ("no: " + g["reason"].get<std::string>()).c_str());
    std::printf("\nEvery name libpfm4 knows here (use as --counters=NAME, with :UMASK where the PMU has them):\n");
    for (const auto& pmu : pmus) {
        std::printf("  %s (%s), %zu events:\n   ", pmu.pmu.c_str(), pmu.description.c_str(), pmu.events.size());
        std::size_t col = 3;
        for (const auto& e : pmu.events) {
            if (col + e.size() + 1 > 100) {
                std::printf("\n   ");
                col = 3;
            }
            std::printf(" %s", e.c_str());
            col += e.size() + 1;
        }
        std::printf("\n");
    }
    std::printf("\n--counters=default counts cycles, instructions, L1-dcache-load-misses, LLC-load-misses and bus-cycles where\n"
                "this PMU offers them, and task-clock, page-faults, context-switches and cpu-migrations.\n");
    return 0;
}

}  // namespace suite
