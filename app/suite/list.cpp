// `suite list`: the kernels and what they accept; with --counters, the events this machine can
// count, and why the others cannot.
#include <algorithm>
#include <cstdio>
#include <iostream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "app/suite/commands.hpp"
#include "app/suite/parse.hpp"
#include "app/suite/run.hpp"
#include "harness/common/text.hpp"
#include "harness/instruments/counters.hpp"
#include "harness/kernel/kernel.hpp"
#include "harness/kernel/patterns.hpp"

namespace suite {
namespace list_command {
namespace {

// The names perf(1) users know, each tried here.
const char* const kGeneric[] = {"cycles",           "instructions",    "cache-references",
                                "cache-misses",     "branches",        "branch-misses",
                                "bus-cycles",       "L1-dcache-loads", "L1-dcache-load-misses",
                                "LLC-loads",        "LLC-load-misses", "LLC-store-misses",
                                "dTLB-load-misses", "task-clock",      "page-faults",
                                "minor-faults",     "major-faults",    "context-switches",
                                "cpu-migrations"};

std::string accesses_text(const KernelInfo& info) {
    std::string out;
    for (const auto& a : info.accesses)
        out += (out.empty() ? "" : ",") + a + (find_pattern(a) && find_pattern(a)->takes_stride ? ":S" : "");
    return out;
}

nlohmann::json params_json(const KernelInfo& info) {
    nlohmann::json out = nlohmann::json::array();
    for (const auto& p : info.params) {
        nlohmann::json one{{"name", p.name}, {"help", p.help}};
        // A named parameter's default is its first name, and the names are listed.
        if (p.choices.empty())
            one["default"] = p.default_value;
        else
            one["default"] = p.choices.front(), one["choices"] = p.choices;
        if (p.numbers_too) one["numbers_too"] = true;  // a number is accepted beside the names
        out.push_back(one);
    }
    return out;
}

// The options that only some kernels take: their variant options and parameters, a line each.
void print_kernel_options() {
    bool any = false;
    for (const auto& e : kernels()) {
        const auto& i = e.info;
        std::vector<std::string> named;
        for (const auto& v : i.variants)
            if (!v.empty() && !is_store_variant(v))
                named.push_back(v + (std::find(i.single_thread_variants.begin(), i.single_thread_variants.end(), v) !=
                                             i.single_thread_variants.end()
                                         ? " (1 thread)"
                                         : ""));
        const bool plain = std::find(i.variants.begin(), i.variants.end(), "") != i.variants.end();
        if (!named.empty() && plain && i.variant_option == "phase")
            named.insert(named.begin(), "all");
        else if (!named.empty() && plain && !i.plain_variant_name.empty())
            named.insert(named.begin(), i.plain_variant_name);
        if (named.empty()) continue;
        if (!any) std::printf("\nOptions of some kernels:\n");
        any = true;
        if (!named.empty()) {
            // "" is the plain kernel, which --phase calls "all".
            const std::string plain_name = i.variant_option == "phase"     ? "all"
                                           : !i.plain_variant_name.empty() ? i.plain_variant_name
                                                                           : "the plain kernel";
            std::string defaults;
            for (const auto& v : i.default_variants)
                defaults += (defaults.empty() ? "" : ",") + (v.empty() ? plain_name : v);
            std::printf("  %-12s --%s=%s (default %s)\n", i.name.c_str(), i.variant_option.c_str(),
                        join(named, ",").c_str(), defaults.empty() ? plain_name.c_str() : defaults.c_str());
        }
    }
    // Parameters, once each, with the kernels that take them.
    std::vector<std::string> names;
    for (const auto& e : kernels())
        for (const auto& p : e.info.params)
            if (std::find(names.begin(), names.end(), p.name) == names.end()) {
                if (!any) std::printf("\nOptions of some kernels:\n");
                any = true;
                names.push_back(p.name);
                std::printf("  --%s=X: %s; %s\n", p.name.c_str(), p.help.c_str(), param_users(p.name).c_str());
            }
}

int list_counters(bool json) {
    const PerfAccess access = perf_access();
    nlohmann::json generic = nlohmann::json::array();
    for (const char* name : kGeneric) {
        CounterSpec spec = parse_counters(name, access).events.front();
        const std::string why = probe_event(spec, access);
        generic.push_back({{"name", name},
                           {"canonical", spec.canonical},
                           {"hardware", spec.hardware},
                           {"available", why.empty()},
                           {"reason", why.empty() ? nlohmann::json(nullptr) : nlohmann::json(why)}});
    }
    const auto pmus = known_events();
    if (json) {
        nlohmann::json p = nlohmann::json::array();
        for (const auto& pmu : pmus)
            p.push_back({{"pmu", pmu.pmu}, {"description", pmu.description}, {"events", pmu.events}});
        std::cout << nlohmann::json{{"scope", access.scope()},
                                    {"perf_event_paranoid", access.paranoid},
                                    {"privileged", access.privileged},
                                    {"generic", generic},
                                    {"pmus", p}}
                         .dump(2)
                  << "\n";
        return 0;
    }
    std::printf("Counting scope here: %s (perf_event_paranoid=%d, %s)\n\n", access.scope().c_str(), access.paranoid,
                access.privileged ? "privileged" : "unprivileged");
    std::printf("%-24s %-9s %s\n", "event", "kind", "counted here?");
    for (const auto& g : generic)
        std::printf("%-24s %-9s %s\n", g["name"].get<std::string>().c_str(),
                    g["hardware"].get<bool>() ? "hardware" : "software",
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
    std::printf(
        "\n--counters=default counts cycles, instructions, L1-dcache-load-misses, LLC-load-misses and bus-cycles "
        "where\n"
        "this PMU offers them, and task-clock, page-faults, context-switches and cpu-migrations.\n");
    return 0;
}

}  // namespace
}  // namespace list_command

int cmd_list(const std::vector<std::string>& args) {
    using namespace list_command;
    CLI::App app{"suite list: the kernels and what they accept"};
    bool json = false, counters = false;
    app.add_flag("--json", json, "machine-readable output");
    app.add_flag("--counters", counters, "the events that can be counted here (generic and this PMU's), and why not");
    if (!parse_command_line(app, "suite list", args)) return 0;
    if (counters) return list_counters(json);
    if (json) {
        nlohmann::json j = nlohmann::json::array();
        for (const auto& e : kernels()) {
            const auto& i = e.info;
            j.push_back({{"name", i.name},
                         {"group", i.group},
                         {"formula", i.formula},
                         {"unit", i.unit},
                         {"axis", i.axis == AccessAxis::pattern ? "pattern" : "ordering"},
                         {"accesses", i.accesses},
                         {"variants", i.variants},
                         {"size", i.size_kind == SizeKind::bytes ? "bytes" : "count"},
                         {"metric", i.metric == Metric::bandwidth ? "bandwidth" : "latency"},
                         {"read_bytes_per_unit", i.read_bytes_per_unit},
                         {"write_bytes_per_unit", i.write_bytes_per_unit},
                         {"flops_per_unit", i.flops_per_unit},
                         {"notes", i.notes},
                         {"variant_option", i.variant_option},
                         {"default_variants", i.default_variants},
                         {"single_thread_variants", i.single_thread_variants},
                         {"params", params_json(i)}});
        }
        std::cout << j.dump(2) << "\n";
        return 0;
    }
    std::printf("%-9s %-8s %-30s %-28s %-7s %-12s %s\n", "kernel", "group", "formula", "patterns/orderings", "stores",
                "B/unit r+w", "flops");
    for (const auto& e : kernels()) {
        const auto& i = e.info;
        char bytes[32];
        std::snprintf(bytes, sizeof bytes, "%g+%g", i.read_bytes_per_unit, i.write_bytes_per_unit);
        std::string stores;  // the --stores choices beside default
        for (const auto& v : i.variants)
            if (is_store_variant(v)) stores += (stores.empty() ? "" : ",") + v;
        std::printf("%-9s %-8s %-30s %-28s %-7s %-12s %g\n", i.name.c_str(), i.group.c_str(), i.formula.c_str(),
                    accesses_text(i).c_str(), stores.empty() ? "-" : stores.c_str(), bytes, i.flops_per_unit);
    }
    print_kernel_options();
    std::printf(
        "\nPlacements: local (first touch by the computing threads), node:N, remote (a node none of the threads\n"
        "runs on), interleave (pages round-robin over all nodes).  Pinning: compact, scatter, none, CPU list.\n"
        "Counters: --counters=default|none|NAME,... (./suite list --counters).  Energy: "
        "--energy=auto|sysfs|perf|none.\n");
    return 0;
}

}  // namespace suite
