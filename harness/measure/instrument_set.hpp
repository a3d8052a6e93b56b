#pragma once
// The instruments of a run besides the clock — event counters and energy — chosen once from
// the options, and their JSON: what the context says about them and what each record measured.
#include <string>

#include <nlohmann/json_fwd.hpp>

#include "harness/instruments/counters.hpp"
#include "harness/instruments/measurements.hpp"
#include "rapl/energy.hpp"

namespace suite {

struct Instruments {
    PerfAccess access;
    CounterSelection counters;
    EnergyMeter energy;
    double energy_baseline_s = 0;  // --energy-baseline: idle seconds measured before the sweep
    int line_bytes = 64;           // last-level cache line, for bytes implied by misses
};

// --counters and --energy as given; UsageError for an unknown event or backend.
Instruments make_instruments(const std::string& counters, const std::string& energy, const std::string& root);

// context["instruments"]: the timer, counters and energy, each with "available" and a reason.
nlohmann::json instruments_context(const Instruments& in, double timer_resolution_ns);

nlohmann::json to_json(const CounterReadings& c);
nlohmann::json to_json(const EnergyReadings& e);

}  // namespace suite
