#pragma once
// The instruments of a run besides the clock — event counters and energy — chosen once from
// the options, and their JSON: what the context says about them and what each record measured.
#include <memory>
#include <string>

#include <nlohmann/json_fwd.hpp>

#include "harness/instruments/counters.hpp"
#include "harness/instruments/energy.hpp"
#include "harness/instruments/measurements.hpp"

namespace suite {

// Move-only: the energy instrument keeps the readings of the point in progress, and two
// copies would share one meter.
struct Instruments {
    Instruments() = default;
    Instruments(Instruments&&) = default;
    Instruments& operator=(Instruments&&) = default;
    Instruments(const Instruments&) = delete;
    Instruments& operator=(const Instruments&) = delete;

    PerfAccess access;
    CounterSelection counters;
    std::shared_ptr<EnergyInstrument> energy = energy_not_requested();  // never null
    double energy_baseline_s = 0;  // --energy-baseline: idle seconds measured before the sweep
    int line_bytes = 64;           // last-level cache line, for bytes implied by misses
};

// --counters and --energy as given; UsageError for an unknown event or backend. The energy
// instrument is the program's (`open_energy`); without one, --energy accepts auto (nothing is
// measured, and the context says why) and none.
Instruments make_instruments(const std::string& counters, const std::string& energy, const EnergyOpener& open_energy);

// context["instruments"]: the timer, counters and energy, each with "available" and a reason.
nlohmann::json instruments_context(const Instruments& in, double timer_resolution_ns);

nlohmann::json to_json(const CounterReadings& c);
nlohmann::json to_json(const EnergyReadings& e);

}  // namespace suite
