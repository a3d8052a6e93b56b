#pragma once
// `suite history`: every record of every run added, in one SQLite file, keyed by machine
// fingerprint, build (context class), commit, branch and point (each rank of an MPI run, and its
// aggregate, a point of its own: PointKey::rank_scope); read back as series for step
// detection (steps.hpp), the window gate (history_gate.hpp) and the dashboard. Adding the same
// run twice stores it once; two processes adding at once both land (each add is one
// BEGIN IMMEDIATE transaction, the other waits up to `wait_ms`). A file that cannot be used
// (corrupt, of a newer schema version, read-only for an add, locked past the wait) is one
// InputError line, thrown before anything in it is changed.
#include <cstdint>
#include <string>
#include <vector>

#include "harness/results/history_series.hpp"
#include "harness/results/result_file.hpp"
#include "harness/results/sqlite_db.hpp"

namespace suite {

// The schema this suite writes; each older version is migrated up in one transaction by `add`.
// 1: meta, runs, records. 2: the indexes that series queries and the gate look runs up by.
// 3: each record's rank scope and host, so that an MPI run's ranks and aggregate are series of their own.
constexpr int history_schema_version = 3;

// The schema version a database file says it has: 0 for a new, empty file. Throws InputError
// when it is not a suite history database (other tables, or no version). The file's structure
// is checked when it is opened (PRAGMA quick_check).
int history_file_version(const SqlDatabase& db);

// Which machine, which build and which commit a run belongs to.
struct RunIdentity {
    std::string fingerprint;    // 16 hex digits: FNV-1a 64 of host, CPU model, sockets, NUMA nodes, cores, PUs, memory
    std::string machine;        // "vm (AMD EPYC, 2 cores)"
    std::string context_class;  // "GNU 12.2.0, -O3 -DNDEBUG -march=native -fopenmp, Release, AVX-512, THP madvise"
    std::string commit, branch, date;
};

// The machine a result's context describes, as RunIdentity::fingerprint: the same value for
// every run on one machine, whatever was run or how it was built.
std::string machine_fingerprint(const nlohmann::json& context);
// `commit` "" takes the file's git_revision; `branch` "" is "unknown".
RunIdentity identify_run(const ResultFile& file, const std::string& commit = "", const std::string& branch = "");
// A point's series splits on its own huge-page setting too: "..., huge pages thp".
std::string series_class(const std::string& run_class, const std::string& hugepages);
// A stable hash of what was measured (the context and every figure of every point, not the
// file's formatting): the same run added twice has the same one.
std::string run_content_hash(const ResultFile& file);

struct HistoryOptions {
    int wait_ms = 10000;  // how long to wait for another process's lock before giving up (exit 2)
    // Open the file read-only even to add: SQLite's own refusal, which a test can reach as root
    // (root writes to a file whatever its mode).
    bool open_read_only = false;
};

struct AddOutcome {
    std::string source;
    std::int64_t run_id = 0;
    bool added = false;         // false: the same run was already there (run_id is that one)
    std::string stored_commit;  // the commit the history has for it
    std::size_t figures = 0;    // records stored (one a figure of a point)
    RunIdentity id;
};

struct SeriesFilter {
    std::string kernel;                     // "" any
    std::vector<std::string> fingerprints;  // empty: any
    std::string context_class;              // "" any (the run-level class)
};

struct MachineSummary {
    std::string fingerprint, machine;
    std::size_t runs = 0, series = 0, context_classes = 0;
    struct Commit {
        std::string commit, branch, latest_date;
        std::size_t runs = 0;
    };
    std::vector<Commit> commits;  // oldest first
};

class History {
public:
    // The file must exist; it is never changed (read-only connection). An older schema version
    // is read as it is.
    static History open_for_reading(const std::string& path, const HistoryOptions& options = {});
    // Created when missing (its directory must exist); refused when it or its directory is
    // read-only; migrated to this suite's schema version.
    static History open_for_adding(const std::string& path, const HistoryOptions& options = {});

    const std::string& path() const { return db_.path(); }
    int schema_version() const { return version_; }

    // All of `files` in one transaction: all land or none does.
    std::vector<AddOutcome> add(const std::vector<ResultFile>& files, const std::string& commit,
                                const std::string& branch);
    // The id of the run with this content, 0 when it is not in the history.
    std::int64_t find_run(const std::string& content_hash) const;
    // The fingerprints whose machine label contains `text`, or that start with it.
    std::vector<std::pair<std::string, std::string>> machines_matching(const std::string& text) const;
    // Every series (verified records only), machine, class and point in order, entries oldest first.
    std::vector<Series> series(const SeriesFilter& filter = {}) const;
    std::vector<MachineSummary> summary() const;
    std::size_t run_count() const;

    // For tests: creates a new database at `path` with the schema of `version` (1.. current).
    static void create_at_version(const std::string& path, int version);

private:
    History(SqlDatabase db, int version) : db_(std::move(db)), version_(version) {}
    SqlDatabase db_;
    int version_ = 0;
};

}  // namespace suite
