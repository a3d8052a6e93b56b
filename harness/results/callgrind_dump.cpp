#include "harness/results/callgrind_dump.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>

#include <nlohmann/json.hpp>

namespace suite {

using nlohmann::json;

double CallgrindDump::get(const std::string& event) const {
    for (const auto& [name, value] : totals)
        if (name == event) return value;
    return NAN;
}

CallgrindDump parse_callgrind_dump(const std::string& text) {
    CallgrindDump d;
    std::vector<std::string> events;
    std::string totals, summary;
    std::istringstream in(text);
    std::string line;
    while (std::getline(in, line)) {
        if (line.rfind("desc: Trigger: ", 0) == 0)
            d.label = line.substr(15);
        else if (line.rfind("events: ", 0) == 0) {
            events.clear();
            std::istringstream e(line.substr(8));
            for (std::string w; e >> w;) events.push_back(w);
        } else if (line.rfind("totals: ", 0) == 0)
            totals = line.substr(8);
        else if (line.rfind("summary: ", 0) == 0)
            summary = line.substr(9);
    }
    const std::string& counts = totals.empty() ? summary : totals;
    if (events.empty() || counts.empty())
        throw std::runtime_error("not a callgrind output file (no events or totals line)");
    std::istringstream c(counts);
    for (const auto& name : events) {
        double v = 0;  // callgrind leaves trailing zero counts out
        if (!(c >> v)) v = 0;
        d.totals.push_back({name, v});
    }
    return d;
}

json callgrind_block(const CallgrindDump& dump, double calls, const std::string& valgrind_version) {
    json per_call = json::object();
    for (const auto& [name, value] : dump.totals) per_call[name] = calls > 0 ? value / calls : 0.0;
    return {{"tool", valgrind_version + " callgrind --cache-sim=yes"},
            {"simulated_caches",
             {{"I1", callgrind_sim_i1},
              {"D1", callgrind_sim_d1},
              {"LL", callgrind_sim_ll},
              {"format", "size_bytes,associativity,line_bytes"}}},
            {"collected", "inside the kernel's calls only (CALLGRIND_TOGGLE_COLLECT around Kernel::run)"},
            {"calls", calls},
            {"per_call", per_call},
            {"note", "time_s and the rates of this record were measured under valgrind and are not hardware figures"}};
}

}  // namespace suite
