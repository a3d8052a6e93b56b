// Issue 52 through the real binary: every input a regular file before it is opened (a FIFO never
// waited on); the roofline's figure claimed with its JSON before the work; an interrupted run
// keeps what it measured beside an earlier complete result, never over it; "not measured" is
// null with a reason, never 0; numbers no measurement can use, memory beyond what the address
// space allows, history identities and options that would be ignored are refused with one line,
// exit 2, and nothing written.
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <tuple>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tests/cli/roofline_size.hpp"
#include "tests/process.hpp"

namespace fs = std::filesystem;
using namespace suite::test;
using nlohmann::json;

namespace {

void expect_refused(const Outcome& r, const std::vector<std::string>& words) {
    EXPECT_EQ(r.status, 2) << describe(r);
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    for (const auto& w : words)
        EXPECT_NE(r.err.find(w), std::string::npos) << "stderr lacks \"" << w << "\"\n" << r.err;
}

void write_file(const std::string& path, const std::string& text) { std::ofstream(path) << text; }

// A small run and this machine's ceilings, measured once for the whole file.
struct Inputs {
    std::string dir, run, roof;
    Inputs() {
        dir = make_temp_dir();
        run = dir + "/run.json";
        roof = dir + "/roof.json";
        Outcome r =
            run_suite({"--kernel=triad", "--sizes=64KiB", "--threads=1", "--reps=2", "--quiet", "--out=" + run});
        EXPECT_EQ(r.status, 0) << describe(r);
        Outcome c = run_suite(
            {"roofline", "--threads=1", "--min-time=0.02", roofline_test_dram_size(), "--no-png", "--out=" + roof});
        EXPECT_EQ(c.status, 0) << describe(c);
    }
};

const Inputs& inputs() {
    static const Inputs i;
    return i;
}

// Starts the suite, waits until its stderr shows `marker` (or, with no marker, `wait_s`), then
// sends `sig`. (A run and mpm show no progress on a stderr that is not a terminal.)
Outcome interrupt_when(const std::vector<std::string>& args, const std::string& marker, int sig, double wait_s = 0) {
    std::vector<std::string> argv{SUITE_BINARY};
    argv.insert(argv.end(), args.begin(), args.end());
    int out = -1, err = -1;
    const pid_t pid = spawn(argv, out, err);
    std::string seen;
    const auto start = std::chrono::steady_clock::now();
    const auto until = start + std::chrono::seconds(60);
    const auto waited = [&] {
        return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() >= wait_s;
    };
    while ((marker.empty() ? !waited() : seen.find(marker) == std::string::npos) &&
           std::chrono::steady_clock::now() < until) {
        char buf[4096];
        pollfd p{err, POLLIN, 0};
        if (poll(&p, 1, 50) > 0) {
            const ssize_t n = read(err, buf, sizeof buf);
            if (n <= 0) break;
            seen.append(buf, static_cast<std::size_t>(n));
        }
    }
    kill(pid, sig);
    Outcome r = finish(pid, out, err, 120);
    r.err = seen + r.err;
    return r;
}

// Every rate or range under `j` that is exactly 0: in a record of work that ran, such a 0
// stands for "not measured". (Counters may count 0 events; an exact kernel's error may be 0.)
void zeros_that_stand_for_nothing(const json& j, const std::string& at, std::vector<std::string>& found) {
    static const std::vector<std::string> rates = {
        "gbps", "gflops", "per_second", "latency_ns", "dt_range", "newton_iterations", "worst_final_residual"};
    if (j.is_object()) {
        for (const auto& [k, v] : j.items()) {
            const std::string here = at + "." + k;
            if (k == "counters") continue;
            const bool rate = std::any_of(rates.begin(), rates.end(),
                                          [&](const std::string& r) { return here.find(r) != std::string::npos; });
            if (rate && v.is_number() && v.get<double>() == 0) found.push_back(here);
            // A solver that did not converge compared no answer: its error is unknown, not 0.
            if (k == "verification" && v.value("solver_failed", false) && !v["max_error"].is_null())
                found.push_back(here + ".max_error");
            zeros_that_stand_for_nothing(v, here, found);
        }
    } else if (j.is_array()) {
        for (std::size_t i = 0; i < j.size(); ++i)
            zeros_that_stand_for_nothing(j[i], at + "[" + std::to_string(i) + "]", found);
    }
}

}  // namespace

TEST(Hardening, EveryInputThatIsAFifoIsRefusedAtOnce) {
    // Nothing writes the FIFO: a reader that opened it would wait for ever (the test's 20 s).
    TempDir dir;
    const std::string fifo = dir.file("f.json");
    ASSERT_EQ(mkfifo(fifo.c_str(), 0644), 0);
    const Inputs& in = inputs();
    const std::vector<std::vector<std::string>> cases = {
        {"roofline", "--place=" + fifo},
        {"roofline", "--place=" + in.run, "--ceilings=" + fifo},
        {"history", "add", fifo, "--db=" + dir.file("h.sqlite")},
        {"history", "check", fifo, "--db=" + dir.file("h.sqlite")},
        {"compare", fifo, in.run},
        {"compare", in.run, fifo},
        {"check", "--baseline", fifo, in.run},
        {"--kernel=fem-spmv", "--mesh=file:" + fifo, "--dry-run"},
    };
    for (const auto& args : cases) {
        const Outcome r = run_suite(args, 20);
        EXPECT_FALSE(r.timed_out) << join(args) << " waited on the FIFO";
        expect_refused(r, {"f.json"});
        EXPECT_TRUE(r.err.find("FIFO") != std::string::npos || r.err.find("not a regular file") != std::string::npos)
            << join(args) << ": " << r.err;
    }
    EXPECT_EQ(names_in(dir.path().string()), std::vector<std::string>{"f.json"});
}

TEST(Hardening, TheRooflineFigureIsClaimedWithItsJsonBeforeTheWork) {
    const Inputs& in = inputs();
    TempDir dir;
    // A result named .png: its figure would go over it.
    const std::string png_input = dir.file("run2.png");
    fs::copy_file(in.run, png_input);
    const std::string before = slurp(png_input);
    expect_refused(
        run_suite({"roofline", "--place=" + png_input, "--ceilings=" + in.roof, "--out=" + dir.file("run2.json")}),
        {"run2.png"});
    EXPECT_EQ(slurp(png_input), before);
    EXPECT_FALSE(fs::exists(dir.file("run2.json")));
    // A figure path that is a FIFO, a directory or a symlink: refused before the JSON is written.
    ASSERT_EQ(mkfifo(dir.file("a.png").c_str(), 0644), 0);
    fs::create_directory(dir.file("b.png"));
    fs::create_symlink(in.run, dir.file("c.png"));
    for (const char* name : {"a", "b", "c"}) {
        expect_refused(run_suite({"roofline", "--place=" + in.run, "--ceilings=" + in.roof,
                                  "--out=" + dir.file(std::string(name) + ".json")}),
                       {std::string(name) + ".png"});
        EXPECT_FALSE(fs::exists(dir.file(std::string(name) + ".json"))) << name;
    }
    // --out=FILE.png: the JSON and the figure would be one file.
    expect_refused(
        run_suite({"roofline", "--ceilings=" + in.roof, "--place=" + in.run, "--out=" + dir.file("roof.png")}),
        {"roof.png", ".json"});
    EXPECT_FALSE(fs::exists(dir.file("roof.png")));
}

TEST(Hardening, AnInterruptedRooflineKeepsWhatItMeasuredBesideTheEarlierCompleteFile) {
    const Inputs& in = inputs();
    TempDir dir;
    const std::string out = dir.file("roof.json");
    fs::copy_file(in.roof, out);
    const std::string before = slurp(out);
    const Outcome r = interrupt_when({"roofline", "--threads=1", "--min-time=0.3", "--no-probe",
                                      roofline_test_dram_size(), "--no-png", "--out=" + out},
                                     "GFLOP/s", SIGINT);
    EXPECT_EQ(r.status, 128 + SIGINT) << describe(r);
    EXPECT_TRUE(slurp(out) == before) << "the complete file was replaced";
    const json doc = json::parse(slurp(dir.file("roof.incomplete.json")));
    EXPECT_EQ(doc["complete"], false);
    ASSERT_EQ(doc["ceilings"].size(), 1u) << doc.dump();
    EXPECT_FALSE(doc["ceilings"][0]["peak"].empty());
    EXPECT_EQ(doc["ceilings"][0]["bandwidth"].size(), doc["levels"].size());
    EXPECT_EQ(validate_by_kind({dir.file("roof.incomplete.json")}).status, 0);
    // A complete rerun takes the name back and removes the incomplete file.
    const Outcome again = run_suite(
        {"roofline", "--threads=1", "--min-time=0.02", roofline_test_dram_size(), "--no-png", "--out=" + out});
    ASSERT_EQ(again.status, 0) << describe(again);
    EXPECT_FALSE(fs::exists(dir.file("roof.incomplete.json")));
}

TEST(Hardening, AnInterruptedRunNeverReplacesAnEarlierCompleteResult) {
    const Inputs& in = inputs();
    TempDir dir;
    const std::string out = dir.file("r.json"), side = dir.file("r.incomplete.json");
    fs::copy_file(in.run, out);
    const std::string before = slurp(out);
    int o = -1, e = -1;
    const pid_t pid = spawn({SUITE_BINARY, "--kernel=latency", "--sizes=64MiB,96MiB,128MiB,192MiB", "--threads=1",
                             "--min-time=0.5", "--out=" + out},
                            o, e);
    // The interim records go beside the complete file from the first point on.
    for (int i = 0; i < 1200 && !fs::exists(side); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(50));
    ASSERT_TRUE(fs::exists(side)) << "no record beside " << out << " within 60 s";
    EXPECT_TRUE(slurp(out) == before) << "the complete file was replaced while the run went on";
    kill(pid, SIGTERM);
    const Outcome r = finish(pid, o, e, 120);
    EXPECT_EQ(r.status, 128 + SIGTERM) << describe(r);
    EXPECT_TRUE(slurp(out) == before) << "the complete file was replaced";
    const json doc = json::parse(slurp(side));
    EXPECT_EQ(doc["complete"], false);
    EXPECT_GE(doc["results"].size(), 1u);
    EXPECT_NE(r.err.find("r.incomplete.json"), std::string::npos) << r.err;
}

TEST(Hardening, AnInterruptedMpmReplaceKeepsTheEarlierSetAndSetsItsOwnApart) {
    TempDir dir;
    const std::string out = dir.file("m");
    const Outcome first = run_suite({"mpm", "--mesh=box:4,4,4", "--steps=5", "--no-png", "--quiet", "--out=" + out});
    ASSERT_EQ(first.status, 0) << describe(first);
    const std::string before = slurp(out + "/mpm.json");
    // About 3 s of steps on 2 cores; stopped after 1 s, inside the stepping.
    const Outcome r = interrupt_when(
        {"mpm", "--mesh=box:16,16,16", "--steps=1000", "--no-png", "--replace", "--out=" + out}, "", SIGINT, 1.0);
    EXPECT_EQ(r.status, 128 + SIGINT) << describe(r);
    EXPECT_TRUE(slurp(out + "/mpm.json") == before);
    const json kept = json::parse(slurp(out + "/.suite-incomplete/mpm.json"));
    EXPECT_EQ(kept["complete"], false);
    EXPECT_NE(r.err.find(".suite-incomplete"), std::string::npos) << r.err;
    // A later --replace takes the directory, the kept incomplete set included.
    const Outcome again =
        run_suite({"mpm", "--mesh=box:4,4,4", "--steps=5", "--no-png", "--quiet", "--replace", "--out=" + out});
    EXPECT_EQ(again.status, 0) << describe(again);
    EXPECT_FALSE(fs::exists(out + "/.suite-incomplete"));
}

TEST(Hardening, NotMeasuredIsNullWithAReasonInEveryRecordKind) {
    TempDir dir;
    std::vector<std::string> found;
    // A run's records: peak-flops moves no bytes.
    const Outcome p = run_suite({"--kernel=peak-flops", "--isa=scalar", "--size=4096", "--threads=1", "--reps=2",
                                 "--quiet", "--out=" + dir.file("peak.json")});
    ASSERT_EQ(p.status, 0) << describe(p);
    const json peak = json::parse(slurp(dir.file("peak.json")));
    const json& bw = peak["results"][0]["bandwidth_gbps"];
    EXPECT_TRUE(bw["stream"]["best"].is_null()) << bw;
    EXPECT_TRUE(bw["hardware_estimate"]["best"].is_null()) << bw;
    EXPECT_TRUE(bw["reason"].is_string()) << bw;
    EXPECT_EQ(validate_against_schema(dir.file("peak.json")).status, 0);
    zeros_that_stand_for_nothing(peak["results"], "peak", found);
    // A CG stopped by --cg-max compared no answer.
    const Outcome cg = run_suite({"--kernel=fem-cg", "--mesh=disk:refine=3", "--cg-max=1", "--threads=1", "--reps=1",
                                  "--quiet", "--out=" + dir.file("cg.json")});
    ASSERT_EQ(cg.status, 3) << describe(cg);
    const json cgdoc = json::parse(slurp(dir.file("cg.json")));
    EXPECT_TRUE(cgdoc["results"][0]["verification"]["max_error"].is_null()) << cgdoc["results"][0]["verification"];
    EXPECT_TRUE(cgdoc["results"][0]["verification"]["max_error_reason"].is_string());
    EXPECT_EQ(validate_against_schema(dir.file("cg.json")).status, 0);
    zeros_that_stand_for_nothing(cgdoc["results"], "cg", found);
    // mpm with no step: no rate, no dt range.
    const Outcome m =
        run_suite({"mpm", "--mesh=box:4,4,4", "--steps=0", "--no-png", "--quiet", "--out=" + dir.file("m")});
    ASSERT_EQ(m.status, 0) << describe(m);
    const json mpm = json::parse(slurp(dir.file("m/mpm.json")));
    EXPECT_TRUE(mpm["timing"]["particle_steps_per_second"].is_null()) << mpm["timing"];
    EXPECT_TRUE(mpm["dt_range"].is_null());
    EXPECT_TRUE(mpm["not_measured"].is_string());
    zeros_that_stand_for_nothing(mpm, "mpm", found);
    // The roofline's ceilings.
    zeros_that_stand_for_nothing(json::parse(slurp(inputs().roof)), "roof", found);
    EXPECT_TRUE(found.empty()) << "zeros that stand for nothing: " << join(found, ", ");
}

TEST(Hardening, CeilingsNoMeasurementCanUseAreRefused) {
    const Inputs& in = inputs();
    TempDir dir;
    json roof = json::parse(slurp(in.roof));
    json zero_peak = roof, zero_bw = roof, incomplete = roof;
    zero_peak["ceilings"][0]["peak"][0]["gflops"] = 0;
    for (auto& l : zero_bw["ceilings"][0]["bandwidth"])
        for (auto& f : l["measured"]) f["gbps"] = 0;
    incomplete["complete"] = false;
    for (const auto& [name, doc, word] :
         std::vector<std::tuple<std::string, json, std::string>>{{"zero_peak.json", zero_peak, "gflops"},
                                                                 {"zero_bw.json", zero_bw, "gbps"},
                                                                 {"incomplete.json", incomplete, "interrupted"}}) {
        write_file(dir.file(name), doc.dump());
        expect_refused(run_suite({"roofline", "--place=" + in.run, "--ceilings=" + dir.file(name),
                                  "--out=" + dir.file("placed.json")}),
                       {name, word});
        EXPECT_FALSE(fs::exists(dir.file("placed.json")));
    }
    // A memory footprint that the last-level cache holds measures the cache.
    expect_refused(run_suite({"roofline", "--dram-size=1MiB", "--out=" + dir.file("r.json")}),
                   {"--dram-size=1MiB", "last-level cache"});
}

TEST(Hardening, MemoryIsEstimatedAgainstTheAddressSpaceLimitToo) {
    if (access("/usr/bin/prlimit", X_OK) != 0) GTEST_SKIP() << "no /usr/bin/prlimit (util-linux)";
    TempDir dir;
    const auto t0 = std::chrono::steady_clock::now();
    expect_refused(run_suite({"roofline", "--dram-size=1000GiB", "--out=" + dir.file("r.json")}),
                   {"--dram-size=1000GiB", "needs about", "available"});
    EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 10)
        << "refused only after measuring";
    // Under a 1 GiB address space an mpm that fits the machine's memory but not the limit.
    std::vector<std::string> argv = {"/usr/bin/prlimit",    "--as=1073741824", SUITE_BINARY, "mpm",
                                     "--mesh=box:96,96,96", "--steps=1",       "--no-png",   "--out=" + dir.file("m")};
    int out = -1, err = -1;
    const pid_t pid = spawn(argv, out, err);
    expect_refused(finish(pid, out, err, 120), {"--mesh=box:96,96,96", "needs about", "available"});
    EXPECT_FALSE(fs::exists(dir.file("m")));
    EXPECT_FALSE(fs::exists(dir.file("r.json")));
}

TEST(Hardening, OneCommitRuleForCommitAndBaseCommit) {
    const Inputs& in = inputs();
    TempDir dir;
    const std::string db = dir.file("h.sqlite");
    for (const std::string& bad :
         std::vector<std::string>{"ab", "abc1234;x", "abc1234\nx", "main", std::string(41, 'a'), "g123456"}) {
        expect_refused(run_suite({"history", "add", in.run, "--db=" + db, "--commit=" + bad}), {"--commit", "hex"});
        expect_refused(run_suite({"history", "check", in.run, "--db=" + db, "--base-commit=" + bad}),
                       {"--base-commit", "hex"});
    }
    EXPECT_FALSE(fs::exists(db));
    const Outcome ok = run_suite({"history", "add", in.run, "--db=" + db, "--commit=ABCDEF1"});
    ASSERT_EQ(ok.status, 0) << describe(ok);
    EXPECT_NE(ok.out.find("commit abcdef1"), std::string::npos) << ok.out;
}

TEST(Hardening, AHistoryAddStoppedMidTransactionIsRolledBackByTheNextReader) {
    const Inputs& in = inputs();
    TempDir dir;
    const std::string db = dir.file("h.sqlite");
    ASSERT_EQ(run_suite({"history", "add", in.run, "--db=" + db, "--commit=1234567"}).status, 0);
    const std::string before = slurp(db);
    // A writer that dies mid-transaction, as a killed `history add` does: its journal stays.
    const Outcome py =
        run_program({SUITE_PYTHON, "-c",
                     "import os, sqlite3, sys\n"
                     "c = sqlite3.connect(sys.argv[1], isolation_level=None)\n"
                     "c.execute('PRAGMA cache_size=1')\n"
                     "c.execute('BEGIN IMMEDIATE')\n"
                     "c.execute('DELETE FROM runs')\n"
                     "c.execute('CREATE TABLE pad(x)')\n"
                     "c.executemany('INSERT INTO pad VALUES (?)', [(os.urandom(2000),) for _ in range(200)])\n"
                     "os._exit(0)\n",
                     db});
    ASSERT_EQ(py.status, 0) << describe(py);
    ASSERT_TRUE(fs::exists(db + "-journal")) << "no journal left: the test did not stop a transaction";
    const Outcome list = run_suite({"history", "list", "--db=" + db});
    EXPECT_EQ(list.status, 0) << describe(list);
    EXPECT_NE(list.out.find("1234567"), std::string::npos) << list.out;
    EXPECT_FALSE(fs::exists(db + "-journal"));
}

TEST(Hardening, RooflineRefusesMeasuringOptionsWithGivenCeilings) {
    const Inputs& in = inputs();
    for (const std::string opt : {"--threads=1", "--pin=compact", "--dram-size=1GiB", "--min-time=0.1", "--no-probe"}) {
        const std::string name = opt.substr(0, opt.find('='));
        expect_refused(run_suite({"roofline", "--place=" + in.run, "--ceilings=" + in.roof, opt}),
                       {name, "--ceilings"});
    }
}
