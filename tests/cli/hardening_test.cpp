// The newer commands keep the promise `suite run` keeps (issue 30), through the real binary
// started as a user's shell starts it: a directory of outputs holds one run's files (a rerun is
// refused, or replaces the whole set with --replace; files the suite did not write are never
// touched; a FIFO, a symlink or an input where an output goes is refused before the work);
// memory is estimated from the mesh before anything is built; values a run would not use, or
// could not use, are refused with the value as typed; a history database is what it says.
// Each case checks the exit status, the one line, and the files left.
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tests/process.hpp"

namespace fs = std::filesystem;
using namespace suite::test;

namespace {

// One line on stderr, exit 2, holding every one of `words`.
void expect_refused(const Outcome& r, const std::vector<std::string>& words) {
    EXPECT_EQ(r.status, 2) << describe(r);
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    for (const auto& w : words)
        EXPECT_NE(r.err.find(w), std::string::npos) << "stderr lacks \"" << w << "\"\n" << r.err;
}

std::vector<std::string> mpm(const std::string& dir, std::vector<std::string> extra) {
    std::vector<std::string> args = {"mpm", "--mesh=box:4,4,4", "--no-png", "--quiet", "--out=" + dir};
    args.insert(args.end(), extra.begin(), extra.end());
    return args;
}

}  // namespace

TEST(DirectoryOfOutputs, ARerunIsRefusedAndReplaceSwapsTheWholeSet) {
    TempDir tmp;
    const std::string dir = tmp.file("dam");
    Outcome r = run_suite(mpm(dir, {"--steps=20", "--vtk-every=5"}), 120);
    ASSERT_EQ(r.status, 0) << describe(r);
    const std::vector<std::string> first = names_in(dir);
    const std::string json = slurp(dir + "/mpm.json");
    ASSERT_NE(std::find(first.begin(), first.end(), "particles_000005.vtu"), first.end());

    r = run_suite(mpm(dir, {"--steps=10", "--vtk-every=10"}), 120);
    expect_refused(r, {"--out=" + dir + " holds the files of an earlier `suite mpm` run", "--replace"});
    EXPECT_EQ(names_in(dir), first) << "nothing written or removed";
    EXPECT_EQ(slurp(dir + "/mpm.json"), json);

    r = run_suite(mpm(dir, {"--steps=10", "--vtk-every=10", "--replace"}), 120);
    ASSERT_EQ(r.status, 0) << describe(r);
    EXPECT_EQ(names_in(dir), (std::vector<std::string>{".suite-files", "front.csv", "mpm.json", "particles.pvd",
                                                       "particles_000000.vtu", "particles_000010.vtu"}))
        << "the earlier snapshots are gone, and no staging directory is left";
    EXPECT_EQ(slurp(dir + "/.suite-files"),
              "suite mpm\nfront.csv\nmpm.json\nparticles.pvd\nparticles_000000.vtu\nparticles_000010.vtu\n");
    EXPECT_EQ(nlohmann::json::parse(slurp(dir + "/mpm.json"))["steps"], 10);
}

TEST(DirectoryOfOutputs, MatrixReplaceRemovesTheEarlierExports) {
    TempDir tmp;
    const std::string dir = tmp.file("m");
    const std::vector<std::string> base = {"matrix",   "--mesh=disk:refine=2", "--reps=1",
                                           "--no-png", "--export=mtx",         "--out=" + dir};
    std::vector<std::string> args = base;
    args.push_back("--ordering=natural,rcm");
    Outcome r = run_suite(args, 120);
    ASSERT_EQ(r.status, 0) << describe(r);
    EXPECT_TRUE(fs::exists(dir + "/rcm.mtx"));
    args = base;
    args.push_back("--ordering=natural");
    expect_refused(run_suite(args, 120), {"holds the files of an earlier `suite matrix` run"});
    args.push_back("--replace");
    r = run_suite(args, 120);
    ASSERT_EQ(r.status, 0) << describe(r);
    EXPECT_EQ(names_in(dir), (std::vector<std::string>{".suite-files", "matrix.json", "matrix.md", "natural.mtx"}))
        << "rcm.mtx of the earlier run is not left beside a matrix.json that lists only natural";
}

TEST(DirectoryOfOutputs, FilesTheSuiteDidNotWriteAreNeverReplaced) {
    TempDir tmp;
    const std::string dir = tmp.file("mine");
    fs::create_directory(dir);
    { std::ofstream(dir + "/notes.txt") << "mine\n"; }
    for (const bool replace : {false, true}) {
        std::vector<std::string> extra = {"--steps=2"};
        if (replace) extra.push_back("--replace");
        expect_refused(run_suite(mpm(dir, extra), 60),
                       {"holds 1 file(s) the suite did not write (notes.txt)", "new or empty directory"});
        EXPECT_EQ(names_in(dir), std::vector<std::string>{"notes.txt"});
        EXPECT_EQ(slurp(dir + "/notes.txt"), "mine\n");
    }
}

TEST(DirectoryOfOutputs, AFifoOrAnInputWhereAnOutputGoesIsRefusedBeforeTheWork) {
    TempDir tmp;
    const std::string dir = tmp.file("fifo");
    fs::create_directory(dir);
    ASSERT_EQ(mkfifo((dir + "/front.csv").c_str(), 0644), 0);
    // Refused when claimed, not after a simulation of 10^6 steps.
    expect_refused(run_suite(mpm(dir, {"--steps=1000000"}), 60), {"front.csv", "did not write"});
    EXPECT_EQ(names_in(dir), std::vector<std::string>{"front.csv"});

    const std::string mdir = tmp.file("withmesh");
    fs::create_directory(mdir);
    fs::copy_file(std::string(SUITE_SOURCE_DIR) + "/../shared/meshes/unit_circle.txt", mdir + "/mesh.txt");
    expect_refused(run_suite({"matrix", "--mesh=file:" + mdir + "/mesh.txt", "--out=" + mdir}, 60),
                   {"mesh.txt", "did not write"});
    EXPECT_EQ(names_in(mdir), std::vector<std::string>{"mesh.txt"});
}

TEST(DirectoryOfOutputs, ASymlinkOrARegularFileAsOutIsRefusedAndSaysWhatItIs) {
    TempDir tmp;
    const std::string real = tmp.file("real"), link = tmp.file("link"), file = tmp.file("afile");
    fs::create_directory(real);
    fs::create_directory_symlink(real, link);
    { std::ofstream(file) << "x\n"; }
    expect_refused(run_suite({"traverse", "--mesh=disk:refine=1", "--no-png", "--out=" + link}, 60),
                   {"--out=" + link + " is a symlink"});
    expect_refused(run_suite(mpm(link, {"--steps=1"}), 60), {"is a symlink"});
    EXPECT_TRUE(names_in(real).empty()) << "nothing written through the link";
    // history html too, which wrote through such a link into the directory it named.
    const std::string db = tmp.file("h.sqlite");
    const Outcome added = run_suite(
        {"history", "add", std::string(SUITE_SOURCE_DIR) + "/tests/fixtures/results/vm-native.json", "--db=" + db});
    ASSERT_EQ(added.status, 0) << describe(added);
    expect_refused(run_suite({"history", "html", "--db=" + db, "--out=" + link}, 60),
                   {"--out=" + link + " is a symlink"});
    EXPECT_TRUE(names_in(real).empty()) << "nothing written through the link";
    expect_refused(run_suite({"traverse", "--mesh=disk:refine=1", "--no-png", "--out=" + file}, 60),
                   {"--out=" + file + " exists and is a regular file, not a directory"});
    EXPECT_EQ(slurp(file), "x\n");
}

TEST(Memory, EstimatedFromTheMeshSpecBeforeAnythingIsBuilt) {
    // Under a 3 GiB address space: a command that built the mesh first would die of bad_alloc
    // (exit 1) before it could refuse; estimated from the spec, each refuses at once (exit 2).
    auto limited = [](std::vector<std::string> args) {
        std::vector<std::string> argv = {"/usr/bin/prlimit", "--as=3221225472", SUITE_BINARY};
        argv.insert(argv.end(), args.begin(), args.end());
        int out = -1, err = -1;
        const pid_t pid = spawn(argv, out, err);
        return finish(pid, out, err, 120);
    };
    if (access("/usr/bin/prlimit", X_OK) != 0) GTEST_SKIP() << "no /usr/bin/prlimit (util-linux)";
    expect_refused(limited({"mpm", "--mesh=box:512,512,512", "--dry-run"}),
                   {"--mesh=box:512,512,512", "needs about", "of memory available"});
    expect_refused(limited({"matrix", "--mesh=disk:refine=12", "--dry-run"}),
                   {"--mesh=disk:refine=12", "needs about", "of memory available"});
    expect_refused(limited({"--kernel=fem-spmv", "--mesh=disk:refine=12", "--dry-run"}),
                   {"fem-spmv on --mesh=disk:refine=12", "needs about"});
    // And a dry run that fits says its estimate.
    const Outcome ok = run_suite({"mpm", "--mesh=box:8,8,8", "--dry-run"}, 60);
    ASSERT_EQ(ok.status, 0) << describe(ok);
    EXPECT_NE(ok.out.find("of memory ("), std::string::npos) << ok.out;
}

TEST(ValuesUsedSilently, EveryCommandRefusesATeamOpenMpWillNotGive) {
    for (const std::vector<std::string>& args :
         {std::vector<std::string>{"mpm", "--threads=2", "--dry-run"},
          std::vector<std::string>{"matrix", "--mesh=disk:refine=2", "--threads=2", "--dry-run"}}) {
        std::vector<std::string> argv = {"/usr/bin/env", "OMP_THREAD_LIMIT=1", SUITE_BINARY};
        argv.insert(argv.end(), args.begin(), args.end());
        int out = -1, err = -1;
        const pid_t pid = spawn(argv, out, err);
        expect_refused(finish(pid, out, err, 60), {"--threads=2", "OMP_THREAD_LIMIT"});
    }
}

TEST(ValuesUsedSilently, OptionsTheRunWouldNotUseAndUnusableMaterialsAreRefusedAsTyped) {
    expect_refused(run_suite({"mpm", "--sort-every=3", "--dry-run"}),
                   {"--sort-every=3", "--particles=seeded never reorders"});
    expect_refused(run_suite({"mpm", "--particles=shuffled", "--sort-every=3", "--dry-run"}),
                   {"--particles=shuffled never reorders"});
    expect_refused(run_suite({"mpm", "--sort-every=auto", "--dry-run"}),
                   {"--sort-every=auto", "--particles=seeded never reorders"});
    expect_refused(run_suite({"mpm", "--particles=shuffled", "--sort-every=auto", "--dry-run"}),
                   {"--sort-every=auto", "--particles=shuffled never reorders"});
    expect_refused(run_suite({"mpm", "--particles=sorted", "--sort-every=5", "--sort-threshold=2", "--dry-run"}),
                   {"--sort-threshold=2", "applies to --sort-every=auto", "not --sort-every=5"});
    expect_refused(run_suite({"mpm", "--sort-threshold=2", "--dry-run"}),
                   {"--sort-threshold=2", "not --particles=seeded"});
    expect_refused(run_suite({"mpm", "--particles=dynamic", "--sort-threshold=0", "--dry-run"}),
                   {"--sort-threshold=0", "> 0"});
    expect_refused(run_suite({"mpm", "--particles=sorted", "--renumber-share=0.1", "--dry-run"}),
                   {"--renumber-share=0.1", "applies to --sort-every=auto", "not --particles=sorted"});
    expect_refused(run_suite({"mpm", "--particles=dynamic", "--sort-every=5", "--renumber-share=0.1", "--dry-run"}),
                   {"--renumber-share=0.1", "with --particles=dynamic, not --sort-every=5"});
    expect_refused(run_suite({"mpm", "--particles=dynamic", "--renumber-share=1.5", "--dry-run"}),
                   {"--renumber-share=1.5", "a number from 0 to 1 (default 0.05)"});
    expect_refused(run_suite({"mpm", "--case=dam-break", "--column=0.3,1,0.6", "--dry-run"}),
                   {"--column does not apply to --case=dam-break"});
    expect_refused(run_suite({"mpm", "--case=dam-collapse", "--viscosity=0.1", "--dry-run"}),
                   {"--viscosity does not apply to --case=dam-collapse"});
    expect_refused(run_suite({"mpm", "--steps=200", "--warm-steps=200", "--dry-run"}),
                   {"--warm-steps=200", "--steps=200 leaves none"});
    expect_refused(run_suite({"mpm", "--particles=unsorted", "--dry-run"}),
                   {"unknown particle order 'unsorted' (now called 'shuffled')"});
    expect_refused(run_suite({"--kernel=mpm-step", "--particles=unsorted", "--dry-run"}),
                   {"no particle order 'unsorted' (did you mean 'shuffled'?)"});
    expect_refused(run_suite({"--kernel=mpm-g2p", "--case=dambreak", "--dry-run"}),
                   {"unknown --case 'dambreak' (did you mean 'dam-break'?)"});
    expect_refused(run_suite({"mpm", "--courant=0.5", "--dt=1e-4", "--dry-run"}),
                   {"--courant=0.5 and --dt=1e-4", "give one of them"});
    expect_refused(run_suite({"mpm", "--young=-0", "--dry-run"}), {"--young=-0:", "must be > 0"});
    expect_refused(run_suite({"mpm", "--young=1e-320", "--dry-run"}), {"--young=1e-320:"});
    expect_refused(run_suite({"mpm", "--density=1e300", "--dry-run"}), {"--density=1e300:"});
    expect_refused(run_suite({"mpm", "--young=1e-2", "--dry-run"}),
                   {"--young=1e-2 --density=1000", "no step could resolve the collapse"});
    expect_refused(run_suite({"--kernel=fem-cg", "--mesh=disk:refine=2", "--cg-max=1e300", "--dry-run"}),
                   {"--cg-max=1e300 for fem-cg"});
    // What stays accepted: --sort-every with an order that sorts, --dt alone.
    EXPECT_EQ(run_suite({"mpm", "--particles=sorted", "--sort-every=3", "--dry-run"}).status, 0);
    EXPECT_EQ(run_suite({"mpm", "--particles=dynamic", "--sort-every=auto", "--sort-threshold=2", "--dry-run"}).status,
              0);
    EXPECT_EQ(run_suite({"mpm", "--particles=dynamic", "--renumber-share=0", "--dry-run"}).status, 0);
    EXPECT_EQ(run_suite({"mpm", "--dt=1e-4", "--dry-run"}).status, 0);
}

TEST(History, ARunWithNoResultsAndAFileThatIsNoDatabaseAreRefused) {
    TempDir tmp;
    nlohmann::json doc =
        nlohmann::json::parse(slurp(std::string(SUITE_SOURCE_DIR) + "/tests/fixtures/results/vm-native.json"));
    doc["results"] = nlohmann::json::array();
    const std::string empty = tmp.file("empty.json"), db = tmp.file("h.sqlite");
    { std::ofstream(empty) << doc.dump(); }
    expect_refused(run_suite({"history", "add", empty, "--db=" + db}), {"empty.json: the run has no results"});
    EXPECT_FALSE(fs::exists(db)) << "no database made for nothing";
    expect_refused(run_suite({"history", "list", "--db=/proc/version"}),
                   {"/proc/version: is not a suite history database"});
}
