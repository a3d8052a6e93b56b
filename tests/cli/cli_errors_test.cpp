// Usage errors of the real ./suite binary: every bad command line must end with exit status 2,
// exactly one line on stderr that starts with "suite: error: " and names the problem and what is
// accepted, nothing on stdout, and no file created or clobbered. The binary is run with
// fork/execv (no shell) in an empty scratch directory, so a stray write shows up there too.
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "harness/machine/topology.hpp"
#include "tests/process.hpp"

namespace fs = std::filesystem;

namespace {

using namespace suite::test;

constexpr double kTimeoutS = 120;  // per run of the binary; the child is killed after this

void write_file(const fs::path& p, const std::string& content) {
    std::ofstream out(p, std::ios::binary | std::ios::trunc);
    out << content;
}

// Replaces every "{tmp}" in `args` with `dir`.
std::vector<std::string> substitute(std::vector<std::string> args, const fs::path& dir) {
    for (auto& a : args)
        for (std::size_t pos; (pos = a.find("{tmp}")) != std::string::npos;) a.replace(pos, 5, dir.string());
    return args;
}

const suite::Topology& topology() {
    static const suite::Topology topo = suite::Topology::load();
    return topo;
}

// The checks every usage error must pass.
void expect_usage_error(const Outcome& r, const std::vector<std::string>& expected) {
    ASSERT_FALSE(r.timed_out) << describe(r);
    EXPECT_EQ(r.status, 2) << describe(r);
    EXPECT_TRUE(r.out.empty()) << "a usage error must be found before anything runs or prints\n" << describe(r);
    EXPECT_EQ(r.err.rfind("suite: error: ", 0), 0u) << describe(r);
    ASSERT_FALSE(r.err.empty()) << describe(r);
    EXPECT_EQ(r.err.back(), '\n') << "stderr must end with a newline\n" << describe(r);
    const auto lines = std::count(r.err.begin(), r.err.end(), '\n');
    EXPECT_EQ(lines, 1) << "stderr must be exactly one line\n" << describe(r);
    for (const auto& s : expected)
        EXPECT_NE(r.err.find(s), std::string::npos) << "stderr lacks \"" << s << "\"\n" << describe(r);
}

// ---------------------------------------------------------------------------------------------
// The table of bad command lines.

enum class Needs { nothing, one_numa_node, fewer_than_8_numa_nodes, fewer_than_999_pus };

struct Case {
    std::string name;                   // the test's name suffix
    std::vector<std::string> args;      // "{tmp}" is replaced by an empty scratch directory
    std::vector<std::string> expected;  // substrings the error line must contain
    Needs needs = Needs::nothing;
};

std::ostream& operator<<(std::ostream& os, const Case& c) { return os << "suite " << join(c.args, " "); }

const std::vector<Case>& cases() {
    static const std::vector<Case> table = {
        // Kernels, patterns, stores, orderings.
        {"UnknownKernelSuggestsAdd",
         {"--kernel=ad", "--out={tmp}/r.json"},
         {"'ad'", "did you mean 'add'?", "copy", "triad", "sin-add", "./suite list"}},
        {"UnknownPatternSuggestsRandom",
         {"--kernel=add", "--pattern=randm", "--out={tmp}/r.json"},
         {"'randm'", "did you mean 'random'?", "sequential", "strided"}},
        {"StridedWithoutStride",
         {"--kernel=add", "--pattern=strided", "--out={tmp}/r.json"},
         {"--pattern=strided", "stride", "strided:8"}},
        {"StridedStrideZero",
         {"--kernel=add", "--pattern=strided:0", "--out={tmp}/r.json"},
         {"strided:0", "positive", "strided:8"}},
        {"StoresNtWithRandomPattern",
         {"--kernel=add", "--stores=nt", "--pattern=random", "--out={tmp}/r.json"},
         {"--stores=nt", "'random'", "sequential"}},
        {"StoresNtWithSinAdd",
         {"--kernel=sin-add", "--stores=nt", "--out={tmp}/r.json"},
         {"--stores=nt", "'sin-add'", "add, copy, scale, store, triad"}},
        {"UnknownHugepagesSuggestsThp",
         {"--kernel=add", "--hugepages=thpp", "--out={tmp}/r.json"},
         {"--hugepages", "'thpp'", "did you mean 'thp'?", "thp, none, system"}},
        {"StoresBogus", {"--kernel=add", "--stores=bogus", "--out={tmp}/r.json"}, {"'bogus'", "default, nt, rep"}},
        {"StoresRepWithTriad",
         {"--kernel=copy,triad", "--stores=rep", "--out={tmp}/r.json"},
         {"--stores=rep", "'triad'", "string-instruction", "copy, store"}},
        {"StoresRepWithStrided",
         {"--kernel=store", "--stores=rep", "--pattern=strided:4", "--out={tmp}/r.json"},
         {"--stores=rep", "'strided:4'", "sequential"}},
        {"OrderingForStreamKernel",
         {"--kernel=triad", "--ordering=morton", "--out={tmp}/r.json"},
         {"'triad'", "--ordering", "--pattern"}},
        {"FemSpmvUnknownStrategySuggestsSymmetric",
         {"--kernel=fem-spmv", "--strategy=symetric", "--out={tmp}/r.json"},
         {"'fem-spmv'", "'symetric'", "did you mean 'symmetric'?", "csr, symmetric"}},
        {"StrategyForStreamKernel",
         {"--kernel=triad", "--strategy=symmetric", "--out={tmp}/r.json"},
         {"'triad'", "--strategy does not apply", "fem-spmv"}},

        // Sizes.
        {"SizeUnknownUnit",
         {"--kernel=add", "--size=12XB", "--out={tmp}/r.json"},
         {"'12XB'", "'XB'", "KiB", "MiB", "GiB", "MB"}},
        {"SizeZero", {"--kernel=add", "--size=0", "--out={tmp}/r.json"}, {"'0'", "at least 1 byte"}},
        {"SizeNegative", {"--kernel=add", "--size=-5MiB", "--out={tmp}/r.json"}, {"'-5MiB'", "positive"}},
        {"SizeLargerThanMemory",
         {"--kernel=add", "--size=100TiB", "--out={tmp}/r.json"},
         {"100TiB", "memory available"}},
        {"SizesSweepBackwards",
         {"--kernel=add", "--sizes=1GiB:16KiB", "--out={tmp}/r.json"},
         {"'1GiB:16KiB'", "first size is larger than the last"}},
        {"SizeAndSizesTogether",
         {"--kernel=add", "--size=1MiB", "--sizes=1MiB:4MiB", "--out={tmp}/r.json"},
         {"--size", "--sizes", "together"}},
        // A size is a whole number of bytes: never rounded.
        {"SizeFractionOfAByte",
         {"--kernel=add", "--size=1.5B", "--out={tmp}/r.json"},
         {"'1.5B'", "1.5 bytes", "not a whole number of bytes"}},
        {"SizeFractionalKiBNotWhole",
         {"--kernel=add", "--size=0.3KiB", "--out={tmp}/r.json"},
         {"'0.3KiB'", "307.2 bytes", "not a whole number"}},
        {"SizesSweepFactorWithExponent",
         {"--kernel=add", "--sizes=1MiB:2MiB:x1e9", "--out={tmp}/r.json"},
         {"'x1e9'", "decimal number above 1", "no exponent"}},
        // A kernel sized by a count is told in its unit, not in bytes.
        {"SfcBuildSizeZeroIsACountOfElements",
         {"--kernel=sfc-build", "--size=0", "--out={tmp}/r.json"},
         {"'0'", "sfc-build", "count of elements", "at least 1"}},
        {"SfcBuildSizeFractionIsRefused",
         {"--kernel=sfc-build", "--size=1.5", "--out={tmp}/r.json"},
         {"'1.5'", "whole number of elements"}},
        {"SfcBuildSizeWithAUnitIsRefused",
         {"--kernel=sfc-build", "--sizes=10000,1MiB", "--out={tmp}/r.json"},
         {"'1MiB'", "count of elements", "no unit"}},

        // Every list: a value given twice is refused, naming it (never dropped, never run twice).
        {"KernelGivenTwice",
         {"--kernel=add,triad,add", "--out={tmp}/r.json"},
         {"--kernel=add,triad,add", "'add' twice"}},
        {"KernelListWithAnEmptyName",
         {"--kernel=add,,triad", "--out={tmp}/r.json"},
         {"--kernel=add,,triad", "empty name"}},
        {"PatternGivenTwice",
         {"--kernel=add", "--pattern=random,sequential,random", "--out={tmp}/r.json"},
         {"--pattern=", "'random' twice"}},
        {"StridedSameStrideWrittenTwoWays",
         {"--kernel=add", "--pattern=strided:8,strided:08", "--out={tmp}/r.json"},
         {"strided:8 twice"}},
        {"OrderingGivenTwice",
         {"--kernel=sfc-build", "--ordering=morton,hilbert,morton", "--out={tmp}/r.json"},
         {"--ordering=", "'morton' twice"}},
        {"PhaseGivenTwice",
         {"--kernel=sfc-build", "--phase=keys,keys", "--out={tmp}/r.json"},
         {"--phase=keys,keys", "'keys' twice"}},
        {"SizesGivenTwice", {"--kernel=add", "--sizes=1MiB,1MiB", "--out={tmp}/r.json"}, {"'1MiB,1MiB'", "1MiB twice"}},
        {"SizesSameSizeWrittenTwoWays",
         {"--kernel=add", "--sizes=1MiB,1024KiB", "--out={tmp}/r.json"},
         {"1MiB twice", "'1MiB' and '1024KiB'"}},
        {"SizesSweepThatRepeatsAPoint",
         {"--kernel=add", "--sizes=64:128:x1.001", "--out={tmp}/r.json"},
         {"'64:128:x1.001'", "64B twice", "larger factor"}},
        {"ThreadsGivenTwice",
         {"--kernel=add", "--threads=1,1-1", "--out={tmp}/r.json"},
         {"thread count 1", "twice", "'1' and '1-1'"}},
        {"CountersGivenTwice",
         {"--kernel=add", "--counters=task-clock,task-clock", "--out={tmp}/r.json"},
         {"'task-clock' twice"}},

        // Threads and pinning.
        {"ThreadsZero", {"--kernel=add", "--threads=0", "--out={tmp}/r.json"}, {"0", "at least 1 thread"}},
        {"ThreadsMoreThanPus",
         {"--kernel=add", "--threads=999", "--out={tmp}/r.json"},
         {"999", "processing units", "at most"},
         Needs::fewer_than_999_pus},
        {"ThreadsBackwardsRange", {"--kernel=add", "--threads=4-1", "--out={tmp}/r.json"}, {"'4-1'", "1-8"}},
        {"ThreadsNegative",
         {"--kernel=add", "--threads=-1", "--out={tmp}/r.json"},
         {"invalid thread count '-1'", "whole numbers from 1"}},
        {"ThreadsRangeWithoutEnd",
         {"--kernel=add", "--threads=1-", "--out={tmp}/r.json"},
         {"invalid thread range '1-'", "FROM-TO"}},
        {"PinRangeWithoutEnd",
         {"--kernel=add", "--pin=0-", "--threads=1", "--out={tmp}/r.json"},
         {"invalid CPU range '0-'", "0,2,4-7"}},
        {"PinBogus",
         {"--kernel=add", "--pin=bogus", "--out={tmp}/r.json"},
         {"'bogus'", "compact", "scatter", "none", "CPU list"}},
        {"PinCpuDoesNotExist",
         {"--kernel=add", "--pin=4096", "--out={tmp}/r.json"},
         {"CPU 4096", "does not have", "./suite info"}},
        {"PinCpuTwice", {"--kernel=add", "--pin=0,0", "--threads=1", "--out={tmp}/r.json"}, {"CPU 0", "twice"}},

        // Placement.
        {"PlacementNodeDoesNotExist",
         {"--kernel=add", "--placement=node:7", "--out={tmp}/r.json"},
         {"node:7", "no NUMA node 7"},
         Needs::fewer_than_8_numa_nodes},
        {"PlacementRemoteOnOneNode",
         {"--kernel=add", "--placement=remote", "--out={tmp}/r.json"},
         {"--placement=remote", "at least 2 NUMA nodes", "local", "interleave"},
         Needs::one_numa_node},
        {"PlacementUnknown",
         {"--kernel=add", "--placement=nowhere", "--out={tmp}/r.json"},
         {"'nowhere'", "local", "node:N", "remote", "interleave"}},
        {"ParticleOrderUnknown",
         {"--kernel=mpm-step", "--mesh=box:6,6,6", "--particles=sortd", "--out={tmp}/r.json"},
         {"no particle order 'sortd'", "did you mean 'sorted'", "seeded, shuffled, sorted, dynamic"}},
        {"ParticlesOnAKernelWithout",
         {"--kernel=add", "--particles=sorted", "--out={tmp}/r.json"},
         {"'add'", "no particle orders", "mpm-g2p, mpm-implicit-solve, mpm-implicit-step, mpm-step"}},
        {"PlacementNodeNumberBeyondInt",
         {"--kernel=add", "--placement=node:99999999999", "--out={tmp}/r.json"},
         {"no NUMA node 99999999999", "its nodes are"}},

        // Repetitions.
        {"RepsZero", {"--kernel=add", "--reps=0", "--out={tmp}/r.json"}, {"--reps=0", "from 1 to 10000000"}},
        {"RepsNotANumber", {"--kernel=add", "--reps=abc", "--out={tmp}/r.json"}, {"--reps", "abc"}},
        {"RepsNegativeIsNotTheAutomaticCount",
         {"--kernel=add", "--reps=-1", "--out={tmp}/r.json"},
         {"--reps=-1: expected a whole number from 1 to 10000000"}},
        {"RepsFraction",
         {"--kernel=add", "--reps=2.5", "--out={tmp}/r.json"},
         {"--reps=2.5", "whole number from 1 to 10000000"}},

        // Seeds: a decimal whole number 0..2^64-1, exactly as typed; the range in digits.
        {"SeedNegative",
         {"--kernel=add", "--seed=-1", "--out={tmp}/r.json"},
         {"--seed=-1: expected a whole number from 0 to 18446744073709551615"}},
        {"SeedAboveTwoToThe64",
         {"--kernel=add", "--seed=18446744073709551616", "--out={tmp}/r.json"},
         {"--seed=18446744073709551616: expected a whole number from 0 to 18446744073709551615"}},
        {"SeedWithPlusSign",
         {"--kernel=add", "--seed=+7", "--out={tmp}/r.json"},
         {"--seed=+7", "0 to 18446744073709551615"}},
        {"TraverseSeedNegative",
         {"traverse", "--seed=-1", "--out={tmp}/t"},
         {"--seed=-1: expected a whole number from 0 to 18446744073709551615"}},
        {"TraverseDepthZero",
         {"traverse", "--depth=0", "--out={tmp}/t"},
         {"--depth=0: expected a whole number from 1 to 32", "2D"}},
        {"TraverseOrderingGivenTwice",
         {"traverse", "--ordering=morton,morton", "--out={tmp}/t"},
         {"--ordering=morton,morton", "'morton' twice"}},
        {"TraverseThreadsGivenTwice", {"traverse", "--threads=4,1-4", "--out={tmp}/t"}, {"thread count 4", "twice"}},
        {"TraverseThreadsAllInAList", {"traverse", "--threads=1,all", "--out={tmp}/t"}, {"'all'", "from 1 to 1024"}},

        // An option given an empty value is an error, in every command (not the next argument
        // taken as its value: --out= once wrote a file named --quiet).
        {"RunOutEmptyValue",
         {"--kernel=add", "--out=", "--quiet"},
         {"--out= has an empty value", "write results to FILE"}},
        {"RunOutEmptySeparateValue", {"--kernel=add", "--out", "", "--quiet"}, {"--out is given an empty value ''"}},
        {"RunPinEmptyValue",
         {"--kernel=add", "--pin=", "--quiet", "--out={tmp}/r.json"},
         {"--pin= has an empty value", "compact"}},
        {"RunKernelEmptyValue", {"--kernel=", "--quiet", "--out={tmp}/r.json"}, {"--kernel= has an empty value"}},
        {"RunFlagWithEmptyValue",
         {"--kernel=add", "--quiet=", "--out={tmp}/r.json"},
         {"--quiet= has an empty value", "takes no value"}},
        {"CheckMarkdownEmptyValue",
         {"check", "--baseline={tmp}/base.json", "--markdown=", "{tmp}/run.json"},
         {"--markdown= has an empty value", "Markdown"}},
        {"TraverseOutEmptyValue", {"traverse", "--out=", "--no-png"}, {"--out= has an empty value", "directory"}},

        // Output.
        {"OutDirectoryDoesNotExist", {"--kernel=add", "--out={tmp}/nosuchdir/r.json"}, {"nosuchdir", "does not exist"}},
        // Nobody, root included, can create a file directly in /proc. Small sizes keep it quick
        // should the check be missing and the benchmark run.
        {"OutDirectoryNotWritable",
         {"--kernel=add", "--size=1MiB", "--threads=1", "--reps=1", "--out=/proc/r.json"},
         {"/proc/r.json", "not writable"}},
        {"OutIsADirectory", {"--kernel=add", "--out={tmp}"}, {"is a directory", "run.json"}},
        {"FormatXml", {"--kernel=add", "--format=xml", "--out={tmp}/r.json"}, {"'xml'", "table, json, csv"}},
        {"FormatTableToFile",
         {"--kernel=add", "--format=table", "--out={tmp}/r.txt"},
         {"--format=table", "json, csv or gbench"}},

        // Options and commands.
        {"UnknownOption", {"--bogus", "--out={tmp}/r.json"}, {"unknown option '--bogus'; see ./suite --help"}},
        {"UnknownCommandSuggestsList", {"lsit"}, {"'lsit'", "did you mean 'list'?", "run, list, info"}},
        {"UnknownOptionSuggestsKernel",
         {"--kernal=add", "--out={tmp}/r.json"},
         {"unknown option '--kernal'", "did you mean '--kernel'?", "./suite --help"}},
        {"UnknownCheckOptionSuggestsTolerance",
         {"check", "--baseline={tmp}/base.json", "--tolerence=5", "{tmp}/run.json"},
         {"unknown option '--tolerence'", "did you mean '--tolerance'?", "./suite check --help"}},
        {"UnknownOptionFarFromAnyHasNoGuess",
         {"--zzzzzzzzzz", "--out={tmp}/r.json"},
         {"unknown option '--zzzzzzzzzz'; see ./suite --help"}},
        {"ListUnknownOption", {"list", "--bogus"}, {"--bogus"}},
    };
    return table;
}

class CliErrorTest : public testing::TestWithParam<Case> {};

TEST_P(CliErrorTest, ExitsTwoWithOneLineAndWritesNothing) {
    const Case& c = GetParam();
    const auto& topo = topology();
    switch (c.needs) {
        case Needs::nothing:
            break;
        case Needs::one_numa_node:
            if (topo.nodes.size() >= 2)
                GTEST_SKIP() << "this machine has " << topo.nodes.size() << " NUMA nodes; the case needs one";
            break;
        case Needs::fewer_than_8_numa_nodes:
            for (const auto& n : topo.nodes)
                if (n.os_index == 7) GTEST_SKIP() << "this machine has a NUMA node 7";
            break;
        case Needs::fewer_than_999_pus:
            if (topo.pu_count() >= 999) GTEST_SKIP() << "this machine has " << topo.pu_count() << " PUs";
            break;
    }

    TempDir dir;
    const auto args = substitute(c.args, dir.path());
    SCOPED_TRACE("suite " + join(args, " "));
    const Outcome r = run_suite(args, kTimeoutS, dir.path());
    expect_usage_error(r, c.expected);
    // The scratch directory is both the working directory and where --out points: it must
    // still be empty (no r.json, no r.json.tmp.*, no nosuchdir/).
    EXPECT_TRUE(dir.entries().empty()) << "files were created: " << join(dir.entries(), ", ");
    for (const auto& a : args) {
        if (a.rfind("--out=/proc/", 0) == 0) {
            EXPECT_FALSE(fs::exists(a.substr(6)));
        }
    }
}

INSTANTIATE_TEST_SUITE_P(Cases, CliErrorTest, testing::ValuesIn(cases()),
                         [](const testing::TestParamInfo<Case>& info) { return info.param.name; });

// ---------------------------------------------------------------------------------------------
// An existing result file given as --out together with a bad option is left byte for byte.

TEST(CliOutputTest, ExistingResultFileUntouchedByUsageErrors) {
    TempDir dir;
    const fs::path file = dir.path() / "r.json";
    const std::string content = "{\"complete\": true, \"records\": [\"keep me\"]}\n\x01\xff binary tail";
    const std::vector<std::vector<std::string>> bad = {
        {"--kernel=ad"},
        {"--kernel=add", "--size=12XB"},
        {"--kernel=add", "--placement=nowhere"},
        {"--kernel=add", "--reps=0"},
        {"--kernel=add", "--stores=nt", "--pattern=random"},
        {"--kernel=add", "--bogus"},
    };
    for (auto args : bad) {
        write_file(file, content);
        fs::last_write_time(file, fs::file_time_type::clock::now() - std::chrono::hours(1));
        const auto mtime = fs::last_write_time(file);
        args.push_back("--out=" + file.string());
        SCOPED_TRACE("suite " + join(args, " "));
        const Outcome r = run_suite(args, kTimeoutS, dir.path());
        expect_usage_error(r, {});
        EXPECT_EQ(slurp(file), content);
        EXPECT_EQ(fs::last_write_time(file), mtime);
        EXPECT_EQ(dir.entries(), std::vector<std::string>{"r.json"}) << "other files were created";
    }
}

// A directory the user cannot write to (a mode 0555 directory; root ignores the mode bits, so
// this one only runs unprivileged; OutDirectoryNotWritable covers root with /proc).
TEST(CliOutputTest, ReadOnlyDirectoryRefused) {
    if (geteuid() == 0) GTEST_SKIP() << "running as root, which can write into a mode 0555 directory";
    TempDir dir;
    const fs::path ro = dir.path() / "ro";
    fs::create_directory(ro);
    fs::permissions(ro, fs::perms::owner_read | fs::perms::owner_exec | fs::perms::group_read | fs::perms::group_exec |
                            fs::perms::others_read | fs::perms::others_exec);
    const Outcome r =
        run_suite({"--kernel=add", "--size=1MiB", "--threads=1", "--reps=1", "--out=" + (ro / "r.json").string()},
                  kTimeoutS, dir.path());
    expect_usage_error(r, {"not writable"});
    EXPECT_TRUE(fs::is_empty(ro));
}

// ---------------------------------------------------------------------------------------------
// The commands that must work.

TEST(CliUsageTest, HelpShowsExamples) {
    TempDir dir;
    const Outcome r = run_suite({"--help"}, kTimeoutS, dir.path());
    ASSERT_FALSE(r.timed_out) << describe(r);
    EXPECT_EQ(r.status, 0) << describe(r);
    EXPECT_NE(r.out.find("Examples:"), std::string::npos) << describe(r);
    EXPECT_NE(r.out.find("--kernel"), std::string::npos) << describe(r);
    EXPECT_TRUE(r.err.empty()) << describe(r);
    EXPECT_TRUE(dir.entries().empty());
}

TEST(CliUsageTest, ListSucceeds) {
    TempDir dir;
    const Outcome r = run_suite({"list"}, kTimeoutS, dir.path());
    ASSERT_FALSE(r.timed_out) << describe(r);
    EXPECT_EQ(r.status, 0) << describe(r);
    for (const char* k : {"copy", "triad", "add", "sin-add", "latency"})
        EXPECT_NE(r.out.find(k), std::string::npos) << k << "\n" << describe(r);
    EXPECT_TRUE(dir.entries().empty());
}

TEST(CliUsageTest, InfoSucceeds) {
    TempDir dir;
    const Outcome r = run_suite({"info"}, kTimeoutS, dir.path());
    ASSERT_FALSE(r.timed_out) << describe(r);
    EXPECT_EQ(r.status, 0) << describe(r);
    EXPECT_NE(r.out.find("NUMA"), std::string::npos) << describe(r);
    EXPECT_TRUE(dir.entries().empty());
}

// The helper itself: exit status and streams come back, and a timeout kills the child
// instead of hanging the test.
TEST(CliHarnessTest, RunnerReportsStatusAndKillsOnTimeout) {
    TempDir dir;
    const Outcome quick = run_suite({"lsit"}, kTimeoutS, dir.path());
    EXPECT_FALSE(quick.timed_out);
    EXPECT_EQ(quick.status, 2);
    EXPECT_TRUE(quick.out.empty());
    EXPECT_FALSE(quick.err.empty());

    const Outcome slow =
        run_suite({"--kernel=add", "--size=64MiB", "--threads=1", "--reps=10000000", "--quiet"}, 1.5, dir.path());
    EXPECT_TRUE(slow.timed_out) << describe(slow);
    EXPECT_EQ(slow.term_signal, SIGKILL) << describe(slow);
    EXPECT_TRUE(dir.entries().empty());
}

}  // namespace
