#pragma once
// Reading result documents (from this machine or any other, from this version of suite or an
// older one) for `suite compare` and `suite check`. Every field the tools use is checked as it
// is read: a truncated, hand-edited or foreign file is an InputError that names the file and
// the field, never a crash and never a figure made up from a missing one.
#include <cmath>
#include <cstdint>
#include <map>
#include <string>
#include <tuple>
#include <vector>

#include <nlohmann/json.hpp>

#include "harness/common/units.hpp"

namespace suite {

// A result file that cannot be used: one line, exit status 2.
struct InputError : UsageError {
    using UsageError::UsageError;
};

// The result-file versions these tools read.
constexpr int readable_schema_version = 1;

enum class Direction { higher_is_better, lower_is_better };

// One figure of a point that can be compared between files.
struct Measure {
    std::string name;  // "bandwidth", "latency", "callgrind Ir", "counter cycles", "energy package-0"
    std::string unit;  // "GB/s", "ns/load", "per call", "per element", "J/call"
    Direction direction = Direction::higher_is_better;
    double best = 0;    // the headline (best repetition) where the file has one, else = median
    double median = 0;  // the statistic compared and gated on
    // Relative spread of the repetitions (robust standard deviation / median); 0 for a
    // deterministic count, and 0 when the file says nothing about the spread.
    double noise = 0;
    // The repetitions in the figure's own units, where the file has them (the timed headline);
    // empty for counters, energy and callgrind counts. `check` tests them against each other.
    std::vector<double> samples;
    // For a count (counters, callgrind): how many events one repetition counted, which says
    // whether a ratio can mean anything (3 -> 5 context switches is not a regression). NAN: not
    // a count, or not known.
    double count_per_call = NAN;
};

// What identifies a point across files: the same kernel, variant, access, size, threads,
// pinning, placement and kernel parameters.
struct PointKey {
    std::string kernel, variant, access;  // access: the pattern or ordering, e.g. "strided:8"
    std::string size_kind;                // "bytes" or "count"
    std::uint64_t size = 0;               // as requested
    int threads = 0;
    std::string pin, placement;
    std::map<std::string, double> params;  // the record's "parameters"; empty when it has none
    auto tie() const { return std::tie(kernel, variant, access, size_kind, size, threads, pin, placement, params); }
    bool operator<(const PointKey& o) const { return tie() < o.tie(); }
    bool operator==(const PointKey& o) const { return tie() == o.tie(); }
    // "add random 64KiB t=2 compact/local" (with the variant: "copy-nt ...", with parameters:
    // "... compact/local tol=1e-08").
    std::string label() const;
    std::string size_label() const;
};

struct LoadedPoint {
    PointKey key;
    bool verified = true;
    bool under_callgrind = false;  // timings were taken under valgrind: only its counts are figures
    std::vector<Measure> measures;  // the headline first
    // Flagged by the run as unstable (the machine was busy, or the repetitions spread): its
    // timings are not to be trusted, so `check` calls it inconclusive. False in older files.
    bool unstable = false;
    std::string unstable_why;  // the reasons, joined
    std::string hugepages;     // what the record asked of huge pages ("none", "thp"); "" in older files
};

struct ResultFile {
    std::string path;
    int schema_version = 0;
    bool complete = true;
    nlohmann::json context;  // as written; read with context_text()
    std::vector<LoadedPoint> points;
    std::vector<std::string> notes;  // e.g. a point that appears twice (the first one is kept)
    // "vm (AMD EPYC)": the host and CPU model, for labels.
    std::string machine_label() const;
};

// Reads and checks `path`; throws InputError (with the path and the offending field) when the
// file is missing, unreadable, not JSON, not a suite result, of another schema_version, or
// lacks a field the tools need.
ResultFile load_result_file(const std::string& path);
// The same, from text already read (for tests and the fuzz test).
ResultFile parse_result_text(const std::string& text, const std::string& path);

}  // namespace suite
