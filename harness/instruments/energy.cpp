#include "harness/instruments/energy.hpp"

#include <stdexcept>

namespace suite {

const ChoiceTable<EnergyChoice>& energy_backends() {
    static const ChoiceTable<EnergyChoice> table{
        "--energy",
        {{"auto", "the powercap files where readable, else the perf power PMU, else none", {EnergyBackend::automatic}},
         {"sysfs", "the powercap files under /sys/class/powercap", {EnergyBackend::sysfs, true}},
         {"perf", "the perf power PMU's energy events", {EnergyBackend::perf, true}},
         {"none", "energy not measured", {EnergyBackend::none}}}};
    return table;
}

const std::string& energy_backend_name(EnergyBackend b) {
    for (const auto& c : energy_backends().all())
        if (c.what.backend == b) return c.name;
    throw std::logic_error("--energy: a backend without a name");
}

std::shared_ptr<EnergyInstrument> energy_not_requested() {
    static NoEnergy none;
    // The aliasing constructor: no owner and no control block, so no allocation; the object
    // outlives every run.
    return std::shared_ptr<EnergyInstrument>(std::shared_ptr<void>(), &none);
}

}  // namespace suite
