// The history database's file policy and schema: which files may be opened for reading or for
// adding, the version a file says it has, and the migrations from each older version. Every
// check runs before the first change, so a file that is refused is left byte for byte as it was.
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "harness/results/history.hpp"

namespace suite {

namespace {

// Migration k (from 1) takes a file from version k-1 to version k. A released one is never
// edited: a change is a new entry, and history_schema_version moves to it.
const char* const history_migrations[] = {
    // 1: the runs and their records, one row a figure of a point.
    R"(CREATE TABLE meta (key TEXT PRIMARY KEY, value TEXT NOT NULL);
       CREATE TABLE runs (
         id INTEGER PRIMARY KEY,
         content_hash TEXT NOT NULL UNIQUE,
         fingerprint TEXT NOT NULL, machine TEXT NOT NULL, context_class TEXT NOT NULL,
         commit_sha TEXT NOT NULL, branch TEXT NOT NULL, date TEXT NOT NULL,
         source TEXT NOT NULL, added TEXT NOT NULL, context TEXT NOT NULL);
       CREATE TABLE records (
         run_id INTEGER NOT NULL REFERENCES runs(id),
         kernel TEXT NOT NULL, variant TEXT NOT NULL, access TEXT NOT NULL, size_kind TEXT NOT NULL,
         size INTEGER NOT NULL, threads INTEGER NOT NULL, pin TEXT NOT NULL, placement TEXT NOT NULL,
         params TEXT NOT NULL, hugepages TEXT NOT NULL,
         figure TEXT NOT NULL, unit TEXT NOT NULL, direction TEXT NOT NULL CHECK (direction IN ('higher', 'lower')),
         median REAL NOT NULL, noise REAL NOT NULL, count_per_call REAL, samples TEXT NOT NULL,
         verified INTEGER NOT NULL, unstable INTEGER NOT NULL, unstable_why TEXT NOT NULL);)",
    // 2: what `history check` and `history steps` look records up by.
    R"(CREATE INDEX runs_by_machine ON runs (fingerprint, context_class, date);
       CREATE INDEX records_by_run ON records (run_id);
       CREATE INDEX records_by_point ON records (kernel, figure, size, threads);)",
    // 3: which rank of an MPI run measured a record (PointKey::rank_scope: "rank 3 of 4",
    // "aggregate of 4 ranks"; "" in a run of one process, as every record before it) and, for a
    // rank, the host it ran on.
    R"(ALTER TABLE records ADD COLUMN rank_scope TEXT NOT NULL DEFAULT '';
       ALTER TABLE records ADD COLUMN rank_host TEXT NOT NULL DEFAULT '';)",
};
static_assert(std::size(history_migrations) == history_schema_version, "one migration a schema version");

[[noreturn]] void refuse_newer(const std::string& path, int version) {
    throw InputError(path + ": schema version " + std::to_string(version) + " is newer than this suite's (" +
                     std::to_string(history_schema_version) +
                     "); a newer suite wrote it, so use that one (nothing was changed)");
}

// Applies the migrations from the file's version up to `to`, inside the caller's transaction.
void migrate_history(SqlDatabase& db, int from, int to) {
    for (int v = from + 1; v <= to; ++v) db.exec(history_migrations[v - 1]);
    db.prepare("INSERT OR REPLACE INTO meta (key, value) VALUES ('schema_version', ?1)")
        .bind(1, std::to_string(to))
        .run();
}

// SQLite's own check of the file's structure (pages, b-trees), without the slower index scan.
void check_history_integrity(const SqlDatabase& db) {
    SqlStatement s = db.prepare("PRAGMA quick_check(1)");
    std::string first = s.step() ? s.text(0) : "no answer";
    // Its report is several lines ("*** in database main ***\nPage 6: ..."): one line here.
    if (const std::string head = "*** in database main ***"; first.rfind(head, 0) == 0) first.erase(0, head.size());
    for (char& c : first)
        if (c == '\n') c = ' ';
    first.erase(0, first.find_first_not_of(' '));
    if (first != "ok")
        throw InputError(db.path() + ": is not a suite history database (SQLite finds it damaged: " + first +
                         "); nothing was changed");
}

struct stat stat_or_missing(const std::string& path, bool& exists) {
    struct stat st {};
    exists = ::stat(path.c_str(), &st) == 0;
    if (!exists && errno != ENOENT) throw InputError(path + ": cannot read it: " + std::strerror(errno));
    if (exists && !S_ISREG(st.st_mode))
        throw InputError(path + ": is not a regular file; give a history database (e.g. results/history.sqlite)");
    // What the file holds, not what stat says of it (a /proc file says 0 bytes and has text):
    // an SQLite database starts with its 16-byte header; only an empty file may lack it.
    if (exists) {
        std::ifstream in(path, std::ios::binary);
        char head[16] = {};
        in.read(head, sizeof head);
        const std::streamsize got = in.gcount();
        static const char sqlite_header[16] = {'S', 'Q', 'L', 'i', 't', 'e', ' ', 'f',
                                               'o', 'r', 'm', 'a', 't', ' ', '3', '\0'};
        if (got > 0 && (got < 16 || std::memcmp(head, sqlite_header, 16) != 0))
            throw InputError(
                path +
                ": is not a suite history database (it does not start as an SQLite file does); nothing was changed");
    }
    return st;
}

}  // namespace

int history_file_version(const SqlDatabase& db) {
    SqlStatement all = db.prepare("SELECT count(*) FROM sqlite_master");
    all.step();
    if (all.integer(0) == 0) return 0;
    SqlStatement meta = db.prepare("SELECT count(*) FROM sqlite_master WHERE type = 'table' AND name = 'meta'");
    meta.step();
    if (meta.integer(0) == 0)
        throw InputError(
            db.path() +
            ": is not a suite history database (an SQLite file without suite's meta table); nothing was changed");
    SqlStatement v = db.prepare("SELECT value FROM meta WHERE key = 'schema_version'");
    const std::string text = v.step() ? v.text(0) : "";
    std::size_t used = 0;
    int version = 0;
    try {
        version = std::stoi(text, &used);
    } catch (const std::exception&) {
        used = 0;
    }
    if (text.empty() || used != text.size() || version < 1)
        throw InputError(
            db.path() +
            ": is not a suite history database (its meta table has no schema version); nothing was changed");
    return version;
}

History History::open_for_reading(const std::string& path, const HistoryOptions& options) {
    bool exists = false;
    stat_or_missing(path, exists);
    if (!exists)
        throw InputError(
            path + ": no history database there; add runs to it first: ./suite history add RUN.json --db " + path);
    // A rollback journal beside it: a `history add` was stopped mid-transaction (or is running).
    // SQLite rolls a stopped one back on the next read, but only through a connection that may
    // write; read-only, it would call the database read-only. So a reader that may write opens
    // it so, and one that may not says what happened.
    const std::string journal = path + "-journal";
    struct stat js {};
    const bool journal_exists = ::stat(journal.c_str(), &js) == 0 && js.st_size > 0;
    const std::filesystem::path parent = std::filesystem::path(path).parent_path();
    const std::string dir = parent.empty() ? "." : parent.string();
    const bool may_recover = journal_exists && ::access(path.c_str(), W_OK) == 0 && ::access(dir.c_str(), W_OK) == 0;
    if (journal_exists && !may_recover)
        throw InputError(path + ": " + journal +
                         " is there: a `suite history add` was stopped mid-transaction, and this user may not write " +
                         dir +
                         " to roll it back; run any history command as a user who may (the runs it was adding "
                         "are not in the database), nothing was changed");
    SqlDatabase db = SqlDatabase::open(path, {may_recover, false, options.wait_ms});
    check_history_integrity(db);
    const int version = history_file_version(db);
    if (version == 0)
        throw InputError(path + ": no run has been added to it yet (./suite history add RUN.json --db " + path + ")");
    if (version > history_schema_version) refuse_newer(path, version);
    return History(std::move(db), version);
}

History History::open_for_adding(const std::string& path, const HistoryOptions& options) {
    bool exists = false;
    stat_or_missing(path, exists);
    // Checked before SQLite opens anything: SQLite writes its rollback journal beside the file.
    const std::filesystem::path parent = std::filesystem::path(path).parent_path();
    const std::string dir = parent.empty() ? "." : parent.string();
    struct stat st {};
    if (::stat(dir.c_str(), &st) != 0 || !S_ISDIR(st.st_mode))
        throw InputError(path + ": its directory " + dir +
                         " does not exist; create it, or give --db a path in an existing one");
    if (exists && ::access(path.c_str(), W_OK) != 0)
        throw InputError(path + ": is read-only (" + std::strerror(errno) +
                         "); suite history add changes it, so nothing was added");
    if (::access(dir.c_str(), W_OK) != 0)
        throw InputError(path + ": its directory " + dir +
                         " is not writable (SQLite keeps its journal beside the file); nothing was added");
    SqlDatabase db =
        SqlDatabase::open(path, {!options.open_read_only, !exists && !options.open_read_only, options.wait_ms});
    if (db.read_only())
        throw InputError(
            path + ": is read-only (SQLite opened it read-only); suite history add changes it, so nothing was added");
    check_history_integrity(db);
    int version = history_file_version(db);
    if (version > history_schema_version) refuse_newer(path, version);
    if (version < history_schema_version) {
        // Another process may migrate (or create) it at the same time: decide under the lock.
        SqlTransaction t(db);
        version = history_file_version(db);
        if (version > history_schema_version) refuse_newer(path, version);
        if (version < history_schema_version) migrate_history(db, version, history_schema_version);
        t.commit();
    }
    return History(std::move(db), history_schema_version);
}

void History::create_at_version(const std::string& path, int version) {
    if (version < 1 || version > history_schema_version) throw std::invalid_argument("no such history schema version");
    SqlDatabase db = SqlDatabase::open(path, {true, true, 10000});
    SqlTransaction t(db);
    migrate_history(db, 0, version);
    t.commit();
}

}  // namespace suite
