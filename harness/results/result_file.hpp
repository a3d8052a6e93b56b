#pragma once
// Reading result documents (from this machine or any other, from this version of suite or an
// older one) for `suite compare` and `suite check`. Every field the tools use is checked as it
// is read: a truncated, hand-edited or foreign file is an InputError that names the file and
// the field, never a crash and never a figure made up from a missing one.
#include <cmath>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <tuple>
#include <vector>

#include <nlohmann/json.hpp>

#include "harness/common/units.hpp"
#include "harness/kernel/param_value.hpp"

namespace suite {

// A result file that cannot be used: one line, exit status 2.
struct InputError : UsageError {
    using UsageError::UsageError;
};

// A record's "parameters" object: numbers as numbers, a named parameter as its name.
nlohmann::json params_json(const Params& params);
// Its inverse for `kernel`'s record; a number where a named parameter is expected is a schema-1
// index, read as its name (v1_param). Throws nlohmann::json::exception for anything else.
Params params_from_json(const nlohmann::json& j, const std::string& kernel);
// A schema-1 record's value of parameter `name`: a named parameter's index read as its name through
// the order that version used (ParamInfo::v1_order, frozen with it); a number, or an index this
// build cannot name (a kernel it lacks), as the number.
ParamValue v1_param(const std::string& kernel, const std::string& name, double value);

// The result-file versions these tools read: 1 (a named parameter stored as its index, read as
// its name through ParamInfo::v1_order) and 2 (stored as its name).
constexpr int oldest_readable_schema_version = 1;
constexpr int readable_schema_version = 2;

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
// pinning, placement and kernel parameters, and in an MPI run which rank measured it.
struct PointKey {
    std::string kernel, variant, access;  // access: the pattern or ordering, e.g. "strided:8"
    std::string size_kind;                // "bytes" or "count"
    std::uint64_t size = 0;               // as requested
    int threads = 0;                      // of the process; of all ranks together in an MPI aggregate
    std::string pin, placement;
    Params params;  // the record's "parameters"; empty when it has none
    // An MPI run (suite-mpi) writes each point once per rank and once for all ranks together:
    // "rank 3 of 4", "aggregate of 4 ranks" (rank_scope_text); "" for a run of one process.
    std::string rank_scope;
    auto tie() const {
        return std::tie(kernel, variant, access, size_kind, size, threads, pin, placement, params, rank_scope);
    }
    bool operator<(const PointKey& o) const { return tie() < o.tie(); }
    bool operator==(const PointKey& o) const { return tie() == o.tie(); }
    // "add random 64KiB t=2 compact/local" (with the variant: "copy-nt ...", with parameters:
    // "... compact/local tol=1e-08", in an MPI run "... compact/local rank 1 of 2").
    std::string label() const;
    // The same with `threads_text` in place of "t=N" (the host view's "t=1/rank").
    std::string label_with_threads(const std::string& threads_text) const;
    std::string size_label() const;
};

// Where a record of an MPI run comes from (the record's `mpi`); scope none in a run of one process.
struct RankOrigin {
    enum class Scope { none, rank, aggregate } scope = Scope::none;
    int ranks = 0;     // in the run
    int rank = -1;     // Scope::rank: which
    std::string host;  // Scope::rank: where it ran
    // Scope::aggregate: the hosts of the run, and the rank (and its host) with the longest best
    // time; spread = that time over the shortest rank's (>= 1).
    int hosts = 0;
    int slowest_rank = -1;
    std::string slowest_host;
    double spread = 1;
};

// "rank 3 of 4" (rank >= 0), "aggregate of 4 ranks" (rank < 0): PointKey::rank_scope.
std::string rank_scope_text(int rank, int ranks);

// The key under which points of different files meet: the point's own, except that the
// aggregate of an MPI run of one rank is the same experiment as a plain run's point (one
// process, its threads), so it meets that point. Ranks and aggregates of runs of more ranks
// meet only the same rank, or the aggregate, of a run of as many ranks.
PointKey matching_key(const PointKey& key);

// The role of a point of the default sweep (record size.role): the cache its size came from.
struct LoadedRole {
    std::string name;               // "L1/2", "L2/2", "L3/2", "DRAM"; "" for a size given
    std::string cache;              // "L1", "L2", "L3"
    std::uint64_t cache_bytes = 0;  // as the record says (one instance for L1/L2, the last level whole)
};

struct LoadedPoint {
    PointKey key;
    LoadedRole role;  // matches points of machines whose caches differ (suite compare)
    bool verified = true;
    bool under_callgrind = false;   // timings were taken under valgrind: only its counts are figures
    std::vector<Measure> measures;  // the headline first
    // Flagged by the run as unstable (the machine was busy, or the repetitions spread): its
    // timings are not to be trusted, so `check` calls it inconclusive. False in older files.
    bool unstable = false;
    std::string unstable_why;  // the reasons, joined
    std::string hugepages;     // what the record asked of huge pages ("none", "thp"); "" in older files
    RankOrigin mpi;            // which rank of an MPI run measured it; Scope::none in a plain run
};

// One host of an MPI run as its context lists it (context.mpi.hosts).
struct LoadedHost {
    std::string host;
    std::vector<int> ranks;  // the world ranks on it, in order
    std::string cpu_model;
    int cores = 0, pus = 0, numa_node_count = 0;
    std::uint64_t memory_bytes = 0;
};

// context.mpi of a run of suite-mpi: the job as rank 0 wrote it.
struct LoadedMpiJob {
    std::string library, layout;  // "Open MPI v4.1.4, ...", "numa" | "split" | "given"
    int ranks = 0;
    std::vector<LoadedHost> hosts;  // each host once, in the order of the file
    const LoadedHost* host_of(int rank) const;
};

struct ResultFile {
    std::string path;
    int schema_version = 0;
    bool complete = true;
    nlohmann::json context;  // as written; read with context_text()
    std::vector<LoadedPoint> points;
    std::vector<std::string> notes;  // e.g. a point that appears twice (the first one is kept)
    // A run of suite-mpi: its ranks and hosts; every record then has its RankOrigin. Empty for
    // a run of one process.
    std::optional<LoadedMpiJob> mpi;
    // "one process", "4 MPI ranks on 2 hosts": what kind of run it was, for messages.
    std::string processes_label() const;
    // "vm (AMD EPYC)": the host and CPU model, for labels.
    std::string machine_label() const;
};

// The text of an input file, read whole: InputError (naming the path) when it is missing,
// unreadable, a directory, empty or over 1 GiB; `example` says what to give instead.
std::string read_input_file(const std::string& path, const std::string& example);
// Reads and checks `path`; throws InputError (with the path and the offending field) when the
// file is missing, unreadable, not JSON, not a suite result, of another schema_version, or
// lacks a field the tools need.
ResultFile load_result_file(const std::string& path);
// The same, from text already read (for tests and the fuzz test).
ResultFile parse_result_text(const std::string& text, const std::string& path);

}  // namespace suite
