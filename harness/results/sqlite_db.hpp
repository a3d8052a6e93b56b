#pragma once
// A small RAII wrapper over the sqlite3 C API, for the history database: a connection, its
// prepared statements and its transactions, each released exactly once, and every SQLite error
// turned into one line that names the file. It knows nothing of suite's tables (history_schema,
// history do). sqlite3.h stays out of this header: SQLite is a private dependency of the library.
#include <cstdint>
#include <string>
#include <utility>

struct sqlite3;
struct sqlite3_stmt;

namespace suite {

// One prepared statement. Columns and parameters are numbered as SQLite numbers them: parameters
// from 1, columns from 0.
class SqlStatement {
public:
    SqlStatement(sqlite3* db, const std::string& sql, const std::string& file);
    SqlStatement(SqlStatement&& o) noexcept
        : db_(std::exchange(o.db_, nullptr)), stmt_(std::exchange(o.stmt_, nullptr)), file_(std::move(o.file_)) {}
    SqlStatement& operator=(SqlStatement&&) = delete;
    SqlStatement(const SqlStatement&) = delete;
    SqlStatement& operator=(const SqlStatement&) = delete;
    ~SqlStatement();

    SqlStatement& bind(int index, std::int64_t value);
    SqlStatement& bind(int index, double value);  // a NaN is bound as NULL
    SqlStatement& bind(int index, const std::string& value);
    // True while there is a row to read; false when the statement is done.
    bool step();
    // Runs a statement that returns no rows (or whose rows are not wanted) to its end.
    void run();
    // Ready to bind and run again (the bindings are kept until rebound).
    void reset();

    bool is_null(int column) const;
    std::int64_t integer(int column) const;
    double real(int column) const;  // NaN for NULL
    std::string text(int column) const;

private:
    sqlite3* db_;
    sqlite3_stmt* stmt_ = nullptr;
    std::string file_;
};

// How to open a database file.
struct SqlOpen {
    bool write = false;           // read-write; otherwise read-only (SQLite then refuses every change)
    bool create = false;          // create the file when it is missing (with write)
    int busy_timeout_ms = 10000;  // how long a statement waits for another connection's lock
};

class SqlDatabase {
public:
    SqlDatabase() = default;
    // Throws InputError when the file cannot be opened.
    static SqlDatabase open(const std::string& path, const SqlOpen& how);
    SqlDatabase(SqlDatabase&& o) noexcept : db_(std::exchange(o.db_, nullptr)), path_(std::move(o.path_)) {}
    SqlDatabase& operator=(SqlDatabase&& o) noexcept;
    SqlDatabase(const SqlDatabase&) = delete;
    SqlDatabase& operator=(const SqlDatabase&) = delete;
    ~SqlDatabase();

    // Runs one or more statements that return no rows.
    void exec(const std::string& sql);
    SqlStatement prepare(const std::string& sql) const;
    // SQLite will refuse to change the file (opened read-only, or the file is not writable).
    bool read_only() const;
    std::int64_t last_insert_id() const;
    const std::string& path() const { return path_; }

    // Turns an SQLite result code into the exception it stands for (see sqlite_db.cpp).
    [[noreturn]] static void fail(sqlite3* db, int code, const std::string& file, const std::string& doing);

private:
    sqlite3* db_ = nullptr;
    std::string path_;
};

// A transaction that rolls back unless committed: BEGIN IMMEDIATE takes the write lock at once
// (waiting up to the busy timeout for another writer), so two writers queue instead of one
// failing half-way; "BEGIN" reads a consistent snapshot.
class SqlTransaction {
public:
    SqlTransaction(SqlDatabase& db, const char* begin = "BEGIN IMMEDIATE");
    SqlTransaction(const SqlTransaction&) = delete;
    SqlTransaction& operator=(const SqlTransaction&) = delete;
    ~SqlTransaction();
    void commit();

private:
    SqlDatabase& db_;
    bool open_ = true;
};

}  // namespace suite
