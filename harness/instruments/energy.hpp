#pragma once
// The energy instrument as the engine sees it: read around every repetition, summarised per
// point, described in the result's context. The engine builds no backend: the program builds one
// from --energy (RAPL, ../../rapl/) and hands the plan an EnergyOpener. Where nothing is
// measured the instrument is a NoEnergy, which says why and never reports 0 J.
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "harness/common/choice_table.hpp"
#include "harness/instruments/instrument.hpp"
#include "harness/instruments/measurements.hpp"

namespace suite {

enum class EnergyBackend { automatic, sysfs, perf, none };

struct EnergyChoice {
    EnergyBackend backend = EnergyBackend::automatic;
    bool names_a_source = false;  // one source asked for by name: the plan says when it cannot measure
};

// --energy's choices, one table: the program's opener (rapl/) and the plan parse --energy through
// it, and messages and --help list its names.
const ChoiceTable<EnergyChoice>& energy_backends();

// The name of `b` in energy_backends(): what a record says its energy was read by.
const std::string& energy_backend_name(EnergyBackend b);

// One domain as the context lists it: what it is, where it is read, and why not (if not).
struct EnergyDomainInfo {
    std::string domain;         // package, core, uncore, dram, psys
    std::optional<int> socket;  // none for psys
    std::string where;          // the file or event it is read from
    std::string reason;         // "": readable
};

class EnergyInstrument : public RepetitionInstrument {
public:
    virtual bool requested() const = 0;              // false: --energy=none
    virtual bool available() const = 0;              // at least one domain can be read
    virtual const std::string& reason() const = 0;   // why not available
    virtual const std::string& backend() const = 0;  // "sysfs", "perf", or "" when none
    virtual std::vector<EnergyDomainInfo> domains() const = 0;
    // The point's summary, from the repetitions since the last take (then forgotten).
    virtual EnergyReadings take(int batch, double units, double stream_bytes, double median_seconds_per_call) = 0;
    // --energy-baseline: sleeps `seconds` and keeps each domain's idle power.
    virtual void measure_idle(double seconds) = 0;
};

// Energy not measured: not requested (--energy=none), or no instrument in this program.
class NoEnergy final : public EnergyInstrument {
public:
    NoEnergy() = default;  // --energy=none
    // Asked for, but nothing here can read it, for `reason`.
    explicit NoEnergy(std::string reason) : requested_(true), reason_(std::move(reason)) {}

    bool requested() const override { return requested_; }
    bool available() const override { return false; }
    const std::string& reason() const override { return reason_; }
    const std::string& backend() const override { return backend_; }
    std::vector<EnergyDomainInfo> domains() const override { return {}; }
    void start() override {}
    void stop(double) override {}
    EnergyReadings take(int, double, double, double) override {
        EnergyReadings out;
        out.requested = requested_;
        out.reason = requested_ ? reason_ : "energy was not requested";
        return out;
    }
    void measure_idle(double) override {}

private:
    bool requested_ = false;
    std::string reason_, backend_;
};

// "Not requested" (--energy=none), shared by every run that asks for no energy: it has no
// state, and it takes no allocation, so that a run with energy off leaves the heap as it was
// (the deterministic mode's per-call counts include libgomp's mallocs, whose cost follows the
// heap's layout).
std::shared_ptr<EnergyInstrument> energy_not_requested();

// Builds the energy instrument for the --energy option's text (never called for "none");
// throws UsageError for a value it does not accept. Never returns null.
using EnergyOpener = std::function<std::unique_ptr<EnergyInstrument>(const std::string& option)>;

}  // namespace suite
