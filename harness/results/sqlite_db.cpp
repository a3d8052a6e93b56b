#include "harness/results/sqlite_db.hpp"

#include <sqlite3.h>

#include <cmath>
#include <stdexcept>

#include "harness/results/result_file.hpp"

namespace suite {

void SqlDatabase::fail(sqlite3* db, int code, const std::string& file, const std::string& doing) {
    const std::string why = db ? sqlite3_errmsg(db) : sqlite3_errstr(code);
    switch (code & 0xff) {
        case SQLITE_BUSY:
        case SQLITE_LOCKED:
            throw InputError(
                file +
                ": locked by another process (another suite history add, or a reader) for longer than the wait; "
                "nothing was changed: try again, or wait longer with --wait=SECONDS");
        case SQLITE_NOTADB:
        case SQLITE_CORRUPT:
            throw InputError(file + ": is not a suite history database (SQLite: " + why + "); nothing was changed");
        case SQLITE_READONLY:
            throw InputError(file + ": is read-only (SQLite: " + why + "); nothing was changed");
        case SQLITE_CANTOPEN:
        case SQLITE_PERM:
        case SQLITE_AUTH:
            throw InputError(file + ": cannot open it (SQLite: " + why + ")");
        default:
            // Disk full, an I/O error: the transaction is rolled back, the run failed (exit 1).
            throw std::runtime_error(file + ": " + doing + " failed (SQLite: " + why + ")");
    }
}

SqlStatement::SqlStatement(sqlite3* db, const std::string& sql, const std::string& file) : db_(db), file_(file) {
    const int rc = sqlite3_prepare_v2(db_, sql.c_str(), static_cast<int>(sql.size() + 1), &stmt_, nullptr);
    if (rc != SQLITE_OK) SqlDatabase::fail(db_, rc, file_, "preparing a query");
}

SqlStatement::~SqlStatement() {
    if (stmt_) sqlite3_finalize(stmt_);
}

SqlStatement& SqlStatement::bind(int index, std::int64_t value) {
    if (const int rc = sqlite3_bind_int64(stmt_, index, value); rc != SQLITE_OK)
        SqlDatabase::fail(db_, rc, file_, "binding a value");
    return *this;
}

SqlStatement& SqlStatement::bind(int index, double value) {
    const int rc = std::isnan(value) ? sqlite3_bind_null(stmt_, index) : sqlite3_bind_double(stmt_, index, value);
    if (rc != SQLITE_OK) SqlDatabase::fail(db_, rc, file_, "binding a value");
    return *this;
}

SqlStatement& SqlStatement::bind(int index, const std::string& value) {
    const int rc = sqlite3_bind_text(stmt_, index, value.data(), static_cast<int>(value.size()), SQLITE_TRANSIENT);
    if (rc != SQLITE_OK) SqlDatabase::fail(db_, rc, file_, "binding a value");
    return *this;
}

bool SqlStatement::step() {
    const int rc = sqlite3_step(stmt_);
    if (rc == SQLITE_ROW) return true;
    if (rc == SQLITE_DONE) return false;
    SqlDatabase::fail(db_, rc, file_, "a query");
}

void SqlStatement::run() {
    while (step()) {
    }
}

void SqlStatement::reset() { sqlite3_reset(stmt_); }

bool SqlStatement::is_null(int column) const { return sqlite3_column_type(stmt_, column) == SQLITE_NULL; }

std::int64_t SqlStatement::integer(int column) const { return sqlite3_column_int64(stmt_, column); }

double SqlStatement::real(int column) const { return is_null(column) ? NAN : sqlite3_column_double(stmt_, column); }

std::string SqlStatement::text(int column) const {
    const auto* p = sqlite3_column_text(stmt_, column);
    return p ? std::string(reinterpret_cast<const char*>(p),
                           static_cast<std::size_t>(sqlite3_column_bytes(stmt_, column)))
             : std::string();
}

SqlDatabase SqlDatabase::open(const std::string& path, const SqlOpen& how) {
    SqlDatabase d;
    d.path_ = path;
    int flags = how.write ? SQLITE_OPEN_READWRITE : SQLITE_OPEN_READONLY;
    if (how.write && how.create) flags |= SQLITE_OPEN_CREATE;
    // No URI names (a path is a path), and one thread a connection.
    flags |= SQLITE_OPEN_NOMUTEX;
    const int rc = sqlite3_open_v2(path.c_str(), &d.db_, flags, nullptr);
    if (rc != SQLITE_OK) fail(d.db_, rc, path, "opening it");
    sqlite3_extended_result_codes(d.db_, 1);
    sqlite3_busy_timeout(d.db_, how.busy_timeout_ms);
    return d;
}

SqlDatabase& SqlDatabase::operator=(SqlDatabase&& o) noexcept {
    if (this != &o) {
        if (db_) sqlite3_close_v2(db_);
        db_ = std::exchange(o.db_, nullptr);
        path_ = std::move(o.path_);
    }
    return *this;
}

SqlDatabase::~SqlDatabase() {
    if (db_) sqlite3_close_v2(db_);
}

void SqlDatabase::exec(const std::string& sql) {
    char* message = nullptr;
    const int rc = sqlite3_exec(db_, sql.c_str(), nullptr, nullptr, &message);
    sqlite3_free(message);  // the same text as sqlite3_errmsg, which fail() reads
    if (rc != SQLITE_OK) fail(db_, rc, path_, "a statement");
}

SqlStatement SqlDatabase::prepare(const std::string& sql) const { return SqlStatement(db_, sql, path_); }

bool SqlDatabase::read_only() const { return sqlite3_db_readonly(db_, "main") == 1; }

std::int64_t SqlDatabase::last_insert_id() const { return sqlite3_last_insert_rowid(db_); }

SqlTransaction::SqlTransaction(SqlDatabase& db, const char* begin) : db_(db) { db_.exec(begin); }

SqlTransaction::~SqlTransaction() {
    if (!open_) return;
    try {
        db_.exec("ROLLBACK");
    } catch (const std::exception&) {
        // SQLite has already rolled back after the error that brought us here.
    }
}

void SqlTransaction::commit() {
    db_.exec("COMMIT");
    open_ = false;
}

}  // namespace suite
