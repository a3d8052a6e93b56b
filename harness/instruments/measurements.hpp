#pragma once
// What the counters and the energy meter measured over the counted repetitions of one point,
// as plain structs. "Not measured" is `available == false` with a reason, never a zero.
#include <optional>
#include <string>
#include <vector>

namespace suite {

// Median, min and max over the counted repetitions, each normalised to one kernel call (a
// repetition of `batch` calls counts `batch` times as much).
struct PerCall {
    double median = 0, min = 0, max = 0;
};

struct EventReading {
    std::string name;       // as asked, e.g. "LLC-load-misses"
    std::string canonical;  // libpfm4's name, e.g. "perf::PERF_COUNT_HW_CACHE_LL:READ:MISS"
    bool hardware = false;
    bool available = false;
    std::string reason;                           // why not available
    PerCall per_call;                             // summed over the team's threads
    std::optional<double> per_element, per_byte;  // median per unit of work / per STREAM byte
    bool multiplexed = false;                     // the kernel shared the PMU: values are scaled up
    std::optional<double> running_fraction;       // time counted / time enabled, over all threads and repetitions
    // A multiplexed event may be off the PMU for a whole repetition: that one has no value, and
    // the statistics are over the others.
    int repetitions_counted = 0, repetitions_not_counted = 0;
};

struct CounterReadings {
    bool requested = false;  // false: --counters=none, nothing to report
    bool available = false;  // at least one event counted
    std::string reason;
    std::string scope;  // "user+kernel" or "user" (perf_event_paranoid forbids kernel mode)
    std::vector<EventReading> events;
    std::vector<std::pair<std::string, std::string>> omitted;  // default events not offered here: name, reason
    // Derived where the inputs were counted.
    std::optional<double> ipc;
    std::optional<std::string> llc_miss_event;
    std::optional<double> llc_miss_bytes_per_call;           // misses x line size
    std::optional<double> llc_miss_bytes_over_stream_bytes;  // what the hardware moved vs the STREAM convention
};

struct DomainEnergy {
    std::string domain;         // package, core, uncore, dram, psys
    std::optional<int> socket;  // none for psys
    bool available = false;
    std::string reason;
    PerCall joules_per_call;
    double joules_total = 0;  // over all counted repetitions
    std::optional<double> watts_median;
    std::optional<double> nj_per_byte, nj_per_element;  // from the median joules per call
    std::optional<double> idle_watts;                   // --energy-baseline
    std::optional<double> joules_above_idle_per_call;   // median, minus idle power x median time
};

struct EnergyReadings {
    bool requested = false;
    bool available = false;
    std::string reason;
    std::string backend;  // "sysfs" or "perf"
    std::vector<DomainEnergy> domains;
};

}  // namespace suite
