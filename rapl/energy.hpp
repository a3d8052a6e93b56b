#pragma once
// Energy from RAPL, read by the runner around each repetition, per domain (package, core,
// uncore, dram, psys) and socket. Two backends: the powercap sysfs tree and the perf `power`
// PMU. Energy that cannot be read, or a counter that does not advance, is reported unavailable
// with the reason, never as 0 J. The sysfs root is injectable (SUITE_SYSFS_ROOT, default /sys)
// so that captured trees under tests/fixtures/ stand in for machines with RAPL.
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "harness/instruments/energy.hpp"
#include "harness/instruments/measurements.hpp"

namespace suite {

// A name of energy_backends(); anything else is a UsageError.
EnergyBackend parse_energy_backend(const std::string& text);

// SUITE_SYSFS_ROOT if set, else "/sys".
std::string sysfs_root();

// One domain of one socket, and how to read its counter.
struct EnergySource {
    std::string domain;         // package, core, uncore, dram, psys (or the zone's own name)
    std::optional<int> socket;  // none for psys
    std::string where;          // the energy_uj file, or the perf event: named in messages
    int fd = -1;                // perf backend: the open event
    double joules_per_unit = 1e-6;
    std::uint64_t max_raw = 0;  // the counter wraps to 0 after this value (0: 64 bits, no wrap)
    std::string reason;         // non-empty: found but unreadable (and why)
};

// Every RAPL zone and subzone under ROOT/class/powercap; `reason` says why there are none.
std::vector<EnergySource> discover_powercap(const std::string& root, std::string& reason);
// The perf power PMU's energy events under ROOT/bus/event_source/devices/power, opened on one
// CPU per socket (its cpumask).
std::vector<EnergySource> discover_perf_power(const std::string& root, std::string& reason);

// Reads one source: false (and `error`) when it cannot be read now.
bool read_raw(const EnergySource& s, std::uint64_t& raw, std::string& error);
// Joules between two raw readings, across at most one wrap-around of the counter.
double joules_between(const EnergySource& s, std::uint64_t begin, std::uint64_t end);

// The energy instrument of a run, from RAPL. Move-only; empty with a reason where nothing can be read.
class EnergyMeter final : public EnergyInstrument {
public:
    EnergyMeter() = default;  // not requested (--energy=none)
    static EnergyMeter open(EnergyBackend backend, const std::string& root);
    EnergyMeter(EnergyMeter&&) noexcept;
    EnergyMeter& operator=(EnergyMeter&&) noexcept;
    EnergyMeter(const EnergyMeter&) = delete;
    EnergyMeter& operator=(const EnergyMeter&) = delete;
    ~EnergyMeter() override;

    bool requested() const override { return requested_; }
    bool available() const override { return !sources_.empty() && reason_.empty(); }
    const std::string& reason() const override { return reason_; }
    const std::string& backend() const override { return backend_; }
    std::vector<EnergyDomainInfo> domains() const override;
    const std::vector<EnergySource>& sources() const { return sources_; }

    void start() override;
    void stop(double seconds) override;  // adds one repetition that took `seconds`
    EnergyReadings take(int batch, double units, double stream_bytes, double median_seconds_per_call) override;
    void measure_idle(double seconds) override;

private:
    bool requested_ = false;
    std::string reason_, backend_;
    std::vector<EnergySource> sources_;
    std::vector<std::uint64_t> begin_;
    std::vector<std::vector<double>> joules_;  // [source][repetition]
    std::vector<double> seconds_;              // [repetition]
    std::vector<std::uint64_t> advanced_;      // [source]: repetitions over which the counter moved
    std::vector<std::uint64_t> last_;          // [source]: the last raw value read, for the reason when it never moved
    std::vector<std::string> lost_;            // [source]: a read failed during the point
    std::vector<std::optional<double>> idle_watts_;
};

// The program's EnergyOpener: --energy's text (parse_energy_backend) opened under sysfs_root().
std::unique_ptr<EnergyInstrument> open_energy(const std::string& option);

}  // namespace suite
