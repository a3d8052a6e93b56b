// `suite history` end to end: the real binary measures twice at a tiny size, both runs are added,
// listed and gated; four `history add` processes started together all land; each database that
// cannot be used is one line on stderr, exit 2, and the same bytes afterwards; steps names the
// commit of a made-up step; usage errors name what is accepted.
#include <gtest/gtest.h>

#include <sys/stat.h>
#include <unistd.h>

#include "harness/results/history.hpp"
#include "tests/process.hpp"
#include "tests/results/history_fixtures.hpp"

using namespace suite;
using namespace suite::test;
using nlohmann::json;

namespace {

void expect_one_line_refusal(const Outcome& r, const std::string& needle) {
    EXPECT_EQ(r.status, 2) << describe(r);
    EXPECT_EQ(r.err.rfind("suite: error: ", 0), 0u) << describe(r);
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << describe(r);
    EXPECT_NE(r.err.find(needle), std::string::npos) << "stderr lacks '" << needle << "'\n" << describe(r);
}

// A made-up run i (3 points, fixture times with 1 % noise), written to DIR/run<i>.json.
std::string write_run(const TempDir& tmp, std::size_t i, Gauss& g) {
    json doc = fixture_run(3);
    stamp(doc, i);
    for (auto& r : doc["results"]) set_times(r, noisy_times(r, 1.0, 0.01, g));
    const std::string path = tmp.file("run" + std::to_string(i) + ".json");
    save_json(doc, path);
    return path;
}

}  // namespace

TEST(HistoryCli, TwoRealRunsAddedListedAndGated) {
    TempDir tmp;
    const std::string db = tmp.file("h.sqlite"), a = tmp.file("a.json"), b = tmp.file("b.json");
    for (const auto& out : {a, b}) {
        Outcome r = run_suite({"--kernel=add", "--pattern=sequential", "--size=64KiB", "--threads=1", "--reps=5",
                               "--quiet", "--out=" + out});
        ASSERT_EQ(r.status, 0) << describe(r);
    }
    Outcome add = run_suite({"history", "add", a, "--db", db, "--commit", "c1c1c1c", "--branch", "main"});
    ASSERT_EQ(add.status, 0) << describe(add);
    EXPECT_NE(add.out.find("added " + a + ": run 1, commit c1c1c1c (branch main)"), std::string::npos) << add.out;
    add = run_suite({"history", "add", b, "--db", db, "--commit", "c2c2c2c"});
    ASSERT_EQ(add.status, 0) << describe(add);
    Outcome again = run_suite({"history", "add", a, "--db", db});
    ASSERT_EQ(again.status, 0) << describe(again);
    EXPECT_NE(again.out.find("already in the history as run 1 (commit c1c1c1c); not added again"), std::string::npos)
        << again.out;
    EXPECT_NE(again.out.find(db + ": 2 run(s)"), std::string::npos) << again.out;

    Outcome list = run_suite({"history", "list", "--db", db});
    ASSERT_EQ(list.status, 0) << describe(list);
    EXPECT_NE(list.out.find("2 run(s) of 1 machine(s)"), std::string::npos) << list.out;
    EXPECT_NE(list.out.find("c1c1c1c "), std::string::npos) << list.out;
    EXPECT_NE(list.out.find("c2c2c2c "), std::string::npos) << list.out;

    // b against the window (run a; b's own commit c2c2c2c left out). A shared machine's timings may
    // differ by more than 10 %: the tolerance is set so high that only the plumbing is tested.
    Outcome check = run_suite({"history", "check", b, "--db", db, "--commit", "c2c2c2c", "--tolerance=1000%"});
    EXPECT_EQ(check.status, 0) << describe(check);
    EXPECT_NE(check.out.find("1 run(s) of the history pooled"), std::string::npos) << check.out;
    EXPECT_NE(check.out.find("1 point(s) compared"), std::string::npos) << check.out;

    Outcome steps = run_suite({"history", "steps", "--db", db, "--kernel", "add"});
    EXPECT_EQ(steps.status, 0) << describe(steps);
    EXPECT_NE(steps.out.find("0 step(s) in "), std::string::npos) << steps.out;  // two runs: too few for a step
}

TEST(HistoryCli, FourAddsStartedTogetherAllLand) {
    TempDir tmp;
    const std::string db = tmp.file("h.sqlite");
    Gauss g(5);
    std::vector<std::string> files;
    for (std::size_t i = 0; i < 4; ++i) files.push_back(write_run(tmp, i, g));
    // Each process creates the database if it is missing: they race from the first byte.
    std::vector<std::pair<pid_t, std::pair<int, int>>> started;
    for (const auto& f : files) {
        int o, e;
        const pid_t pid = spawn({SUITE_BINARY, "history", "add", f, "--db", db}, o, e);
        started.push_back({pid, {o, e}});
    }
    for (auto& [pid, fds] : started) {
        const Outcome r = finish(pid, fds.first, fds.second, 120);
        EXPECT_EQ(r.status, 0) << describe(r);
    }
    EXPECT_EQ(History::open_for_reading(db).run_count(), 4u);
}

TEST(HistoryCli, EachUnusableDatabaseIsOneLineExitTwoAndUntouched) {
    TempDir tmp;
    Gauss g(8);
    const std::string run = write_run(tmp, 0, g);
    const std::string good = tmp.file("good.sqlite");
    ASSERT_EQ(run_suite({"history", "add", run, "--db", good}).status, 0);
    auto refused = [&](const std::string& db, const std::vector<std::string>& args, const std::string& needle) {
        const std::uint64_t before = file_hash(db);
        expect_one_line_refusal(run_suite(args), needle);
        EXPECT_EQ(file_hash(db), before) << db << " was changed by: " << join(args);
    };
    // Random bytes.
    const std::string corrupt = tmp.file("corrupt.sqlite");
    std::string bytes(4096, '\0');
    for (std::size_t i = 0; i < bytes.size(); ++i) bytes[i] = static_cast<char>((i * 2654435761u) >> 13);
    std::ofstream(corrupt, std::ios::binary) << bytes;
    refused(corrupt, {"history", "add", run, "--db", corrupt}, "is not a suite history database");
    refused(corrupt, {"history", "list", "--db", corrupt}, "is not a suite history database");
    // A newer schema version.
    const std::string newer = tmp.file("newer.sqlite");
    std::filesystem::copy_file(good, newer);
    SqlDatabase::open(newer, {true, false, 1000}).exec("UPDATE meta SET value = '99' WHERE key = 'schema_version'");
    refused(newer, {"history", "add", write_run(tmp, 1, g), "--db", newer},
            "schema version 99 is newer than this suite's");
    refused(newer, {"history", "steps", "--db", newer}, "schema version 99 is newer");
    // Locked by another connection for longer than --wait.
    {
        LockHolder holder(good);
        ASSERT_TRUE(holder.held());
        refused(good, {"history", "add", write_run(tmp, 2, g), "--db", good, "--wait=0"}, "locked by another process");
        refused(good, {"history", "check", run, "--db", good, "--wait=1"}, "locked by another process");
    }
    // A result file that cannot be used changes nothing either.
    refused(good, {"history", "add", tmp.file("missing.json"), "--db", good}, "missing.json");
    EXPECT_EQ(History::open_for_reading(good).run_count(), 1u);
    // Last, as it may be skipped. Read-only: mode 0444 in a directory anyone may write. Root
    // writes whatever the mode, so as root the command runs as uid 65534 (setpriv).
    {
        namespace fs = std::filesystem;
        fs::permissions(tmp.path(), fs::perms::others_exec | fs::perms::others_read, fs::perm_options::add);
        fs::create_directory(tmp.file("shared"));
        fs::permissions(tmp.file("shared"), fs::perms::all, fs::perm_options::add);
        const std::string ro = tmp.file("shared/ro.sqlite");
        fs::copy_file(good, ro);
        ASSERT_EQ(chmod(ro.c_str(), 0444), 0);
        const std::uint64_t before = file_hash(ro);
        std::vector<std::string> argv;
        if (geteuid() == 0) argv = {"/usr/bin/setpriv", "--reuid=65534", "--regid=65534", "--clear-groups"};
        for (const auto& a : {std::string(SUITE_BINARY), std::string("history"), std::string("add"),
                              write_run(tmp, 3, g), std::string("--db"), ro})
            argv.push_back(a);
        const Outcome r = run_program(argv, 120);
        if (r.status != 2 && r.err.find("Permission denied") != std::string::npos &&
            r.err.find("suite:") == std::string::npos)
            GTEST_SKIP() << "uid 65534 cannot reach the binary here: " << r.err;
        expect_one_line_refusal(r, "is read-only");
        EXPECT_EQ(file_hash(ro), before);
    }
}

TEST(HistoryCli, UsageErrorsNameWhatIsAccepted) {
    TempDir tmp;
    expect_one_line_refusal(run_suite({"history"}),
                            "history needs a subcommand: add, list, steps, check, noise or html");
    expect_one_line_refusal(run_suite({"history", "chek"}), "(did you mean 'check'?)");
    expect_one_line_refusal(run_suite({"history", "add", "--db", tmp.file("h.sqlite")}),
                            "history add needs at least one result file");
    expect_one_line_refusal(run_suite({"history", "list", "--db", tmp.file("none.sqlite")}),
                            "no history database there");
    EXPECT_TRUE(tmp.entries().empty()) << "a reader created nothing";
    expect_one_line_refusal(run_suite({"histroy"}), "(did you mean 'history'?)");
    Outcome help = run_suite({"history", "--help"});
    EXPECT_EQ(help.status, 0);
    EXPECT_NE(help.out.find("./suite history check RUN.json"), std::string::npos) << help.out;
}

TEST(HistoryCli, StepsNamesTheCommitOfAMadeUpStep) {
    TempDir tmp;
    const std::string db = tmp.file("h.sqlite");
    Gauss g(3);
    std::vector<std::string> args{"history", "add", "--db", db};
    for (std::size_t i = 0; i < 20; ++i) {
        json doc = fixture_run(2);
        stamp(doc, i);
        for (std::size_t p = 0; p < 2; ++p) {
            auto& r = doc["results"][p];
            set_times(r, noisy_times(r, (1 + 0.01 * g()) * (p == 1 && i >= 10 ? 1.25 : 1.0), 0.005, g));
        }
        save_json(doc, tmp.file("r" + std::to_string(i) + ".json"));
        args.push_back(tmp.file("r" + std::to_string(i) + ".json"));
    }
    ASSERT_EQ(run_suite(args).status, 0);
    Outcome r = run_suite({"history", "steps", "--db", db, "--machine", "vm"});
    ASSERT_EQ(r.status, 0) << describe(r);
    EXPECT_NE(r.out.find("1 step(s) in 2 series"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find(made_up_commit(10)), std::string::npos) << r.out;
    EXPECT_TRUE(r.out.find("-19.") != std::string::npos || r.out.find("-20.") != std::string::npos ||
                r.out.find("-21.") != std::string::npos)
        << r.out;
    EXPECT_NE(r.out.find("worse"), std::string::npos) << r.out;
    expect_one_line_refusal(run_suite({"history", "steps", "--db", db, "--machine", "nowhere"}), "no machine in");
    expect_one_line_refusal(run_suite({"history", "steps", "--db", db, "--kernel", "cpy"}), "(did you mean 'copy'?)");
}
