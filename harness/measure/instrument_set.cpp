#include "harness/measure/instrument_set.hpp"

#include <stdexcept>

#include <nlohmann/json.hpp>

#include "harness/common/units.hpp"

namespace suite {

namespace {

nlohmann::json opt(const std::optional<double>& v) { return v ? nlohmann::json(*v) : nlohmann::json(nullptr); }
nlohmann::json reason_or_null(bool available, const std::string& reason) {
    return available ? nlohmann::json(nullptr) : nlohmann::json(reason);
}
nlohmann::json socket_json(const std::optional<int>& s) { return s ? nlohmann::json(*s) : nlohmann::json(nullptr); }
nlohmann::json per_call(const PerCall& p) { return {{"median", p.median}, {"min", p.min}, {"max", p.max}}; }

}  // namespace

Instruments make_instruments(const std::string& counters, const std::string& energy, const EnergyOpener& open_energy) {
    Instruments in;
    in.access = perf_access();
    const Choice<EnergyChoice>* choice = energy_backends().find(energy);
    const auto is = [&](EnergyBackend b) { return choice && choice->what.backend == b; };
    if (is(EnergyBackend::none)) {
        in.energy = energy_not_requested();
    } else if (open_energy) {
        in.energy = open_energy(energy);  // its usage errors before the counters'
        if (!in.energy) throw std::logic_error("the energy opener returned no instrument");
    } else if (is(EnergyBackend::automatic)) {
        in.energy = std::make_shared<NoEnergy>("this program has no energy instrument");
    } else {
        // Without an opener only the choices that need no backend mean anything.
        const ChoiceTable<EnergyChoice> without = energy_backends().subset([](const EnergyChoice& c) {
            return c.backend == EnergyBackend::automatic || c.backend == EnergyBackend::none;
        });
        throw UsageError("--energy=" + energy + ": this program reads no energy; accepted: " + without.accepted());
    }
    in.counters = parse_counters(counters, in.access);
    return in;
}

nlohmann::json instruments_context(const Instruments& in, double timer_resolution_ns) {
    nlohmann::json events = nlohmann::json::array();
    bool any = false;
    for (const auto& e : in.counters.events) {
        const std::string why = probe_event(e, in.access);
        any = any || why.empty();
        events.push_back({{"name", e.name},
                          {"canonical", e.canonical},
                          {"hardware", e.hardware},
                          {"available", why.empty()},
                          {"reason", why.empty() ? nlohmann::json(nullptr) : nlohmann::json(why)}});
    }
    nlohmann::json omitted = nlohmann::json::array();
    for (const auto& [name, why] : in.counters.omitted) omitted.push_back({{"name", name}, {"reason", why}});
    std::string reason;
    if (!in.counters.requested)
        reason = "not requested (--counters=none)";
    else if (!any)
        reason = in.counters.events.empty() ? "no event can be opened here"
                                            : "none of the requested events can be opened here";
    nlohmann::json counters = {{"available", any},
                               {"reason", reason_or_null(any, reason)},
                               {"scope", in.access.scope()},
                               {"perf_event_paranoid", in.access.paranoid},
                               {"privileged", in.access.privileged},
                               {"events", events},
                               {"omitted", omitted}};
    // The hardware side on its own: "available" above is true here on software events alone.
    bool hw = false;
    std::string hw_reason = "no hardware event was requested";
    for (const auto& e : events)
        if (e["hardware"].get<bool>()) {
            hw = hw || e["available"].get<bool>();
            if (!hw) hw_reason = e["reason"].get<std::string>();
        }
    if (!hw && !in.counters.omitted.empty()) hw_reason = in.counters.omitted.front().second;
    counters["hardware"] = {{"available", hw}, {"reason", reason_or_null(hw, hw_reason)}};

    nlohmann::json domains = nlohmann::json::array();
    for (const auto& s : in.energy->domains())
        domains.push_back({{"domain", s.domain},
                           {"socket", socket_json(s.socket)},
                           {"source", s.where},
                           {"available", s.reason.empty()},
                           {"reason", reason_or_null(s.reason.empty(), s.reason)}});
    const EnergyInstrument& meter = *in.energy;
    const bool energy_ok = meter.available();
    nlohmann::json energy = {
        {"available", energy_ok},
        {"reason", reason_or_null(energy_ok, meter.requested() ? meter.reason() : "not requested (--energy=none)")},
        {"backend", meter.backend().empty() ? nlohmann::json(nullptr) : nlohmann::json(meter.backend())},
        {"domains", domains},
        {"baseline_s", in.energy_baseline_s > 0 ? nlohmann::json(in.energy_baseline_s) : nlohmann::json(nullptr)}};
    return {{"timer",
             {{"available", true},
              {"clock", "CLOCK_MONOTONIC (std::chrono::steady_clock)"},
              {"resolution_ns", timer_resolution_ns}}},
            {"perf_counters", counters},
            {"energy", energy}};
}

nlohmann::json to_json(const CounterReadings& c) {
    if (!c.requested) return {{"available", false}, {"reason", "not requested (--counters=none)"}};
    nlohmann::json events = nlohmann::json::array();
    for (const auto& e : c.events) {
        nlohmann::json j = {{"name", e.name},
                            {"canonical", e.canonical},
                            {"kind", e.hardware ? "hardware" : "software"},
                            {"available", e.available},
                            {"reason", reason_or_null(e.available, e.reason)}};
        if (e.available) {
            j["per_call"] = per_call(e.per_call);
            j["per_element"] = opt(e.per_element);
            j["per_byte"] = opt(e.per_byte);
            j["multiplexed"] = e.multiplexed;
            j["running_fraction"] = opt(e.running_fraction);
            if (e.multiplexed) {
                j["repetitions_counted"] = e.repetitions_counted;
                j["repetitions_not_counted"] = e.repetitions_not_counted;
            }
        } else {
            j["per_call"] = nullptr;
        }
        events.push_back(j);
    }
    nlohmann::json omitted = nlohmann::json::array();
    for (const auto& [name, why] : c.omitted) omitted.push_back({{"name", name}, {"reason", why}});
    return {{"available", c.available},
            {"reason", reason_or_null(c.available, c.reason)},
            {"scope", c.scope},
            {"events", events},
            {"omitted", omitted},
            {"derived",
             {{"ipc", opt(c.ipc)},
              {"llc_miss_event", c.llc_miss_event ? nlohmann::json(*c.llc_miss_event) : nlohmann::json(nullptr)},
              {"llc_miss_bytes_per_call", opt(c.llc_miss_bytes_per_call)},
              {"llc_miss_bytes_over_stream_bytes", opt(c.llc_miss_bytes_over_stream_bytes)}}}};
}

nlohmann::json to_json(const EnergyReadings& e) {
    if (!e.requested) return {{"available", false}, {"reason", "not requested (--energy=none)"}};
    nlohmann::json domains = nlohmann::json::array();
    for (const auto& d : e.domains) {
        nlohmann::json j = {{"domain", d.domain},
                            {"socket", socket_json(d.socket)},
                            {"available", d.available},
                            {"reason", reason_or_null(d.available, d.reason)}};
        if (d.available) {
            j["joules_per_call"] = per_call(d.joules_per_call);
            j["joules_total"] = d.joules_total;
            j["watts_median"] = opt(d.watts_median);
            j["nj_per_byte"] = opt(d.nj_per_byte);
            j["nj_per_element"] = opt(d.nj_per_element);
            j["idle_watts"] = opt(d.idle_watts);
            j["joules_above_idle_per_call"] = opt(d.joules_above_idle_per_call);
        } else {
            j["joules_per_call"] = nullptr;
        }
        domains.push_back(j);
    }
    return {{"available", e.available},
            {"reason", reason_or_null(e.available, e.reason)},
            {"backend", e.backend.empty() ? nlohmann::json(nullptr) : nlohmann::json(e.backend)},
            {"domains", domains}};
}

}  // namespace suite
