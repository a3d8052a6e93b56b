// `suite info`: the machine as hwloc sees it, the caches measured beside (--probe), and what can
// be measured here.
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "app/suite/commands.hpp"
#include "app/suite/defaults.hpp"
#include "app/suite/parse.hpp"
#include "harness/machine/topology.hpp"
#include "harness/measure/cache_probe.hpp"
#include "harness/measure/instrument_set.hpp"
#include "harness/results/context.hpp"
#include "harness/results/context_fields.hpp"
#include "rapl/energy.hpp"

namespace suite {

int cmd_info(const std::vector<std::string>& args) {
    CLI::App app{"suite info: the machine as hwloc sees it"};
    bool json = false, probe = false;
    app.add_flag("--json", json, "machine-readable output");
    app.add_flag("--probe", probe,
                 "also measure the caches this process really gets (pointer chase and load bandwidth, a few seconds)");
    if (!parse_command_line(app, "suite info", args)) return 0;
    const Topology topo = Topology::load();
    std::optional<CacheProbe> measured;
    if (probe) measured = probe_caches(topo, probe_options());
    // What a result's context would say about measuring here.
    const Instruments instruments = make_instruments("default", "auto", open_energy);
    const nlohmann::json context = build_context(topo, {}, instruments, bandwidth_convention());
    if (json) {
        nlohmann::json j = to_json(topo);
        for (const char* key :
             {"instruments", "transparent_hugepages", "frequency_governor", "instruction_set", "string_ops"})
            if (context.contains(key)) j[key] = context[key];  // string_ops: x86-64 only
        if (measured) j["caches_measured"] = to_json(*measured, topo);
        std::cout << j.dump(2) << "\n";
        return 0;
    }
    std::cout << format_table(topo);
    if (measured) std::cout << "\n" << format_probe(*measured, topo);
    std::cout << "\nWhat can be measured here\n";
    auto state = [](const nlohmann::json& inst) {
        return inst["available"].get<bool>() ? std::string("available")
                                             : "not available (" + inst["reason"].get<std::string>() + ")";
    };
    for (const auto& [name, inst] : context["instruments"].items()) {
        std::cout << "  " << name << ": " << state(inst) << "\n";
        if (name == "perf_counters") {
            std::cout << "    hardware events: " << state(inst["hardware"]) << "\n    counted here by default:";
            for (const auto& e : inst["events"])
                if (e["available"].get<bool>()) std::cout << " " << e["name"].get<std::string>();
            std::cout << " (scope " << inst["scope"].get<std::string>() << ")\n";
        }
        if (name == "energy")
            for (const auto& d : inst["domains"])
                std::cout << "    " << d["domain"].get<std::string>() << " " << d["source"].get<std::string>() << ": "
                          << state(d) << "\n";
    }
    for (const char* key : {"transparent_hugepages", "frequency_governor"}) {
        const auto& v = context[key];
        std::cout << "  " << key << ": "
                  << (v["value"].is_null() ? "unknown (" + v["reason"].get<std::string>() + ")"
                                           : v["value"].get<std::string>())
                  << "\n";
    }
    std::cout << "  built for: " << instruction_set_text(context["instruction_set"]) << ", "
              << context["instruction_set"]["nt_store_bits"].get<int>() << "-bit streaming stores\n";
    if (!context.contains("string_ops")) return 0;  // x86-64 only: the rep variants' instructions
    const auto& strings = context["string_ops"];
    auto flag = [&](const char* key) {
        return strings[key].is_null() ? std::string("unknown") : strings[key].get<bool>() ? "yes" : "no";
    };
    std::cout << "  fast strings (the rep variants): ERMS " << flag("erms") << ", FSRM " << flag("fsrm")
              << (strings.contains("reason") ? " (" + strings["reason"].get<std::string>() + ")" : std::string())
              << "\n";
    return 0;
}

}  // namespace suite
