// The history database (harness/results/history.hpp): a run is stored once however often it is
// added; a file of an older schema version is read as it is and migrated by the next add, its
// rows kept; and every file that cannot be used (a newer version, random bytes, a damaged page,
// another program's SQLite file, read-only, locked) is refused with one InputError line before
// anything in it changes: the same bytes before and after.
#include <gtest/gtest.h>

#include <sys/stat.h>
#include <unistd.h>

#include <fstream>

#include "harness/results/history.hpp"
#include "tests/process.hpp"
#include "tests/results/history_fixtures.hpp"

using namespace suite;
using namespace suite::test;
using nlohmann::json;

namespace {

ResultFile made_up(std::size_t i, std::size_t points = 3) {
    json doc = fixture_run(points);
    stamp(doc, i);
    return parse_result_text(doc.dump(), "run" + std::to_string(i) + ".json");
}

// Runs `open` expecting an InputError: its message has `needle` and is one line, and the file's
// bytes are the same afterwards.
template <class F>
void expect_refused_untouched(const std::string& path, const std::string& needle, F open) {
    const std::uint64_t before = file_hash(path);
    const auto size = std::filesystem::file_size(path);
    try {
        open();
        ADD_FAILURE() << "not refused: " << path;
    } catch (const InputError& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find(needle), std::string::npos) << what;
        EXPECT_EQ(what.find('\n'), std::string::npos) << what;
    }
    EXPECT_EQ(file_hash(path), before) << "the refused file was changed";
    EXPECT_EQ(std::filesystem::file_size(path), size);
    EXPECT_FALSE(std::filesystem::exists(path + "-journal"));
}

void set_version(const std::string& path, int version) {
    SqlDatabase db = SqlDatabase::open(path, {true, false, 1000});
    db.prepare("UPDATE meta SET value = ?1 WHERE key = 'schema_version'").bind(1, std::to_string(version)).run();
}

}  // namespace

TEST(HistoryDb, TheSameRunAddedTwiceIsStoredOnce) {
    TempDir tmp;
    const std::string db = tmp.file("h.sqlite");
    const ResultFile a = made_up(0), b = made_up(1);
    {
        History h = History::open_for_adding(db);
        const auto first = h.add({a}, "", "main");
        ASSERT_EQ(first.size(), 1u);
        EXPECT_TRUE(first[0].added);
        EXPECT_EQ(first[0].figures, 3u);
        EXPECT_EQ(first[0].stored_commit, made_up_commit(0));
        // Again, and once more in the same call beside a new run.
        const auto again = h.add({a, b, b}, "other-commit", "main");
        EXPECT_FALSE(again[0].added);
        EXPECT_EQ(again[0].run_id, first[0].run_id);
        EXPECT_EQ(again[0].stored_commit, made_up_commit(0)) << "the first commit stays";
        EXPECT_TRUE(again[1].added);
        EXPECT_FALSE(again[2].added);
        EXPECT_EQ(h.run_count(), 2u);
    }
    // The same measurements in a file formatted otherwise are the same run.
    json doc = fixture_run(3);
    stamp(doc, 0);
    EXPECT_EQ(run_content_hash(parse_result_text(doc.dump(4), "elsewhere.json")), run_content_hash(a));
    History h = History::open_for_reading(db);
    EXPECT_EQ(h.run_count(), 2u);
    const auto series = h.series();
    ASSERT_EQ(series.size(), 3u);
    for (const auto& s : series) {
        ASSERT_EQ(s.entries.size(), 2u) << s.key.label();
        EXPECT_EQ(s.entries[0].commit, made_up_commit(0));
        EXPECT_EQ(s.entries[1].commit, "other-commit");
        EXPECT_EQ(s.entries[0].samples.size(), 5u);
        EXPECT_EQ(s.figure, "bandwidth");
    }
}

TEST(HistoryDb, AnOlderSchemaVersionIsReadAsItIsAndMigratedKeepingItsRows) {
    for (int version = 1; version < history_schema_version; ++version) {
        SCOPED_TRACE("a file of schema version " + std::to_string(version));
        TempDir tmp;
        const std::string db = tmp.file("old.sqlite");
        History::create_at_version(db, version);
        {
            // A run as versions 1 and 2 stored it: no rank columns (every run was of one process).
            SqlDatabase raw = SqlDatabase::open(db, {true, false, 1000});
            raw.exec(
                "INSERT INTO runs VALUES (7, 'hash', 'fp', 'old box (CPU, 2 cores)', 'class', 'abc123', 'main', "
                "'2025-01-01T00:00:00Z', "
                "'a.json', '2025-01-01T00:00:00Z', '{}');"
                "INSERT INTO records VALUES (7, 'add', '', 'random', 'bytes', 65536, 1, 'compact', 'local', '{}', '', "
                "'bandwidth', 'GB/s', "
                "'higher', 12.5, 0.01, NULL, '[12.0,12.5,13.0]', 1, 0, '');");
        }
        {
            // Read as it is (reading never changes the file), its series and summary included.
            const std::uint64_t before = file_hash(db);
            const History old = History::open_for_reading(db);
            EXPECT_EQ(old.schema_version(), version);
            const auto series = old.series();
            ASSERT_EQ(series.size(), 1u);
            EXPECT_EQ(series[0].key.rank_scope, "");
            EXPECT_EQ(series[0].entries.at(0).median, 12.5);
            EXPECT_EQ(old.summary().at(0).series, 1u);
            EXPECT_EQ(file_hash(db), before);
        }
        History h = History::open_for_adding(db);
        EXPECT_EQ(h.schema_version(), history_schema_version);
        h.add({made_up(0)}, "", "");
        const auto series = h.series();
        ASSERT_EQ(series.size(), 4u);
        EXPECT_EQ(series.front().machine, "old box (CPU, 2 cores)");  // sorted by machine
        EXPECT_EQ(series.front().entries.at(0).samples, (std::vector<double>{12.0, 12.5, 13.0}));
        for (const auto& s : series) EXPECT_EQ(s.key.rank_scope, "") << s.key.label();
        SqlDatabase raw = SqlDatabase::open(db, {false, false, 1000});
        SqlStatement v = raw.prepare("SELECT value FROM meta WHERE key = 'schema_version'");
        ASSERT_TRUE(v.step());
        EXPECT_EQ(v.text(0), std::to_string(history_schema_version));
        SqlStatement index =
            raw.prepare("SELECT count(*) FROM sqlite_master WHERE type = 'index' AND name = 'records_by_point'");
        index.step();
        EXPECT_EQ(index.integer(0), 1);
        // The old row has the new columns, empty: a record of a run of one process.
        SqlStatement old_row = raw.prepare("SELECT rank_scope, rank_host FROM records WHERE run_id = 7");
        ASSERT_TRUE(old_row.step());
        EXPECT_EQ(old_row.text(0), "");
        EXPECT_EQ(old_row.text(1), "");
    }
}

TEST(HistoryDb, ANewerSchemaVersionIsRefusedUntouched) {
    TempDir tmp;
    const std::string db = tmp.file("new.sqlite");
    History::open_for_adding(db).add({made_up(0)}, "", "");
    set_version(db, history_schema_version + 1);
    const std::string needle = "schema version " + std::to_string(history_schema_version + 1) + " is newer";
    expect_refused_untouched(db, needle, [&] { History::open_for_adding(db).add({made_up(1)}, "", ""); });
    expect_refused_untouched(db, needle, [&] { History::open_for_reading(db); });
}

TEST(HistoryDb, RandomBytesAreNotAHistoryDatabase) {
    TempDir tmp;
    const std::string db = tmp.file("random.sqlite");
    std::mt19937_64 rng(42);
    std::string bytes(8192, '\0');
    for (auto& c : bytes) c = static_cast<char>(rng());
    std::ofstream(db, std::ios::binary) << bytes;
    expect_refused_untouched(db, "is not a suite history database",
                             [&] { History::open_for_adding(db).add({made_up(0)}, "", ""); });
    expect_refused_untouched(db, "is not a suite history database", [&] { History::open_for_reading(db); });
}

TEST(HistoryDb, ADamagedPageIsRefusedUntouched) {
    TempDir tmp;
    const std::string db = tmp.file("damaged.sqlite");
    {
        History h = History::open_for_adding(db);
        for (std::size_t i = 0; i < 4; ++i) h.add({made_up(i, 8)}, "", "");
    }
    // The header stays valid; every page after the first two becomes garbage.
    std::string bytes = slurp(db);
    ASSERT_GT(bytes.size(), 3 * 4096u);
    for (std::size_t i = 2 * 4096; i < bytes.size(); ++i) bytes[i] = static_cast<char>(i * 131 + 7);
    std::ofstream(db, std::ios::binary | std::ios::trunc) << bytes;
    expect_refused_untouched(db, "is not a suite history database",
                             [&] { History::open_for_adding(db).add({made_up(9)}, "", ""); });
}

TEST(HistoryDb, AnotherProgramsSqliteFileIsRefusedUntouched) {
    TempDir tmp;
    const std::string db = tmp.file("other.sqlite");
    SqlDatabase::open(db, {true, true, 1000})
        .exec("CREATE TABLE notes (text TEXT); INSERT INTO notes VALUES ('mine');");
    expect_refused_untouched(db, "without suite's meta table",
                             [&] { History::open_for_adding(db).add({made_up(0)}, "", ""); });
}

TEST(HistoryDb, AddRefusesAFileSqliteOpensReadOnly) {
    // The refusal path as root too: SQLite opens it read-only, as it does a file it cannot write.
    TempDir tmp;
    const std::string db = tmp.file("h.sqlite");
    History::open_for_adding(db).add({made_up(0)}, "", "");
    HistoryOptions o;
    o.open_read_only = true;
    expect_refused_untouched(db, "is read-only", [&] { History::open_for_adding(db, o).add({made_up(1)}, "", ""); });
    EXPECT_EQ(History::open_for_reading(db).run_count(), 1u);
}

TEST(HistoryDb, AddRefusesAFileWithoutWritePermission) {
    if (geteuid() == 0)
        GTEST_SKIP()
            << "running as root, which writes a mode 0444 file (AddRefusesAFileSqliteOpensReadOnly covers the refusal)";
    TempDir tmp;
    const std::string db = tmp.file("h.sqlite");
    History::open_for_adding(db).add({made_up(0)}, "", "");
    ASSERT_EQ(chmod(db.c_str(), 0444), 0);
    expect_refused_untouched(db, "is read-only", [&] { History::open_for_adding(db).add({made_up(1)}, "", ""); });
    EXPECT_EQ(History::open_for_reading(db).run_count(), 1u) << "reading a read-only history is fine";
}

TEST(HistoryDb, ALockHeldLongerThanTheWaitIsRefusedUntouched) {
    TempDir tmp;
    const std::string db = tmp.file("h.sqlite");
    History::open_for_adding(db).add({made_up(0)}, "", "");
    HistoryOptions o;
    o.wait_ms = 200;
    {
        LockHolder holder(db);
        ASSERT_TRUE(holder.held());
        expect_refused_untouched(db, "locked by another process",
                                 [&] { History::open_for_adding(db, o).add({made_up(1)}, "", ""); });
        expect_refused_untouched(db, "locked by another process", [&] { History::open_for_reading(db, o); });
    }
    // Released: the same add lands.
    EXPECT_TRUE(History::open_for_adding(db, o).add({made_up(1)}, "", "")[0].added);
}

TEST(HistoryDb, AMissingDatabaseIsNotCreatedByReaders) {
    TempDir tmp;
    const std::string db = tmp.file("none.sqlite");
    EXPECT_THROW(History::open_for_reading(db), InputError);
    EXPECT_FALSE(std::filesystem::exists(db));
    EXPECT_THROW(History::open_for_adding(tmp.file("no/such/dir/h.sqlite")), InputError);
    EXPECT_THROW(History::open_for_adding(tmp.path().string()), InputError) << "a directory";
}

TEST(HistoryDb, RunIdentityFingerprintsTheMachineAndClassesTheBuild) {
    json doc = fixture_run(1);
    const RunIdentity a = identify_run(parse_result_text(doc.dump(), "a.json"), "", "");
    EXPECT_EQ(a.fingerprint.size(), 16u);
    EXPECT_EQ(a.machine, "vm (AMD EPYC, 2 cores)");
    EXPECT_EQ(a.commit, "2ddd7e4d2055-dirty");
    EXPECT_EQ(a.branch, "unknown");
    EXPECT_NE(a.context_class.find("-march=native"), std::string::npos) << a.context_class;
    EXPECT_NE(a.context_class.find("THP madvise"), std::string::npos) << a.context_class;
    doc["context"]["compiler_flags"] = "-O2";
    doc["context"]["date"] = "2030-01-01T00:00:00Z";
    const RunIdentity b = identify_run(parse_result_text(doc.dump(), "b.json"), "abc", "main");
    EXPECT_EQ(b.fingerprint, a.fingerprint) << "the same machine";
    EXPECT_NE(b.context_class, a.context_class) << "another build";
    EXPECT_EQ(b.commit, "abc");
    doc["context"]["cores"] = 4;
    EXPECT_NE(identify_run(parse_result_text(doc.dump(), "c.json")).fingerprint, a.fingerprint);
}
