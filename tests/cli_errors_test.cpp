// Usage errors of the real ./suite binary: every bad command line must end with exit status 2,
// exactly one line on stderr that starts with "suite: error: " and names the problem and what is
// accepted, nothing on stdout, and no file created or clobbered. The binary is run with
// fork/execv (no shell) in an empty scratch directory, so a stray write shows up there too.
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <system_error>
#include <vector>

#include <gtest/gtest.h>

#include "harness/topology.hpp"

namespace fs = std::filesystem;

namespace {

// ---------------------------------------------------------------------------------------------
// Running the binary.

struct RunResult {
    int exit_code = -1;    // WEXITSTATUS when the child exited normally, else -1
    int term_signal = 0;   // WTERMSIG when the child was killed by a signal
    bool timed_out = false;
    std::string out;
    std::string err;

    std::string describe() const {
        std::ostringstream s;
        s << "exit code " << exit_code;
        if (term_signal) s << ", killed by signal " << term_signal;
        if (timed_out) s << " (timed out)";
        s << "\n--- stdout ---\n" << out << "\n--- stderr ---\n" << err << "\n---";
        return s.str();
    }
};

// Runs SUITE_BINARY with `args` (argv[1..]) in directory `cwd`, stdin from /dev/null, and
// collects stdout, stderr and the exit status. The child is killed after `timeout`.
RunResult run_suite(const std::vector<std::string>& args, const fs::path& cwd = {},
                    std::chrono::milliseconds timeout = std::chrono::seconds(120)) {
    RunResult r;
    int out_pipe[2], err_pipe[2];
    if (pipe2(out_pipe, O_CLOEXEC) != 0 || pipe2(err_pipe, O_CLOEXEC) != 0) {
        ADD_FAILURE() << "pipe2: " << std::strerror(errno);
        return r;
    }
    std::vector<std::string> storage{SUITE_BINARY};
    storage.insert(storage.end(), args.begin(), args.end());
    std::vector<char*> argv;
    for (auto& s : storage) argv.push_back(s.data());
    argv.push_back(nullptr);
    const std::string dir = cwd.string();

    const pid_t pid = fork();
    if (pid < 0) {
        ADD_FAILURE() << "fork: " << std::strerror(errno);
        return r;
    }
    if (pid == 0) {
        // Child: only async-signal-safe calls from here on.
        int devnull = open("/dev/null", O_RDONLY);
        if (devnull >= 0) dup2(devnull, STDIN_FILENO);
        dup2(out_pipe[1], STDOUT_FILENO);
        dup2(err_pipe[1], STDERR_FILENO);
        if (!dir.empty() && chdir(dir.c_str()) != 0) _exit(126);
        execv(argv[0], argv.data());
        const char msg[] = "cli_errors_test: execv failed\n";
        (void)!write(STDERR_FILENO, msg, sizeof msg - 1);
        _exit(127);
    }
    close(out_pipe[1]);
    close(err_pipe[1]);

    const auto deadline = std::chrono::steady_clock::now() + timeout;
    pollfd fds[2] = {{out_pipe[0], POLLIN, 0}, {err_pipe[0], POLLIN, 0}};
    std::string* sinks[2] = {&r.out, &r.err};
    int open_fds = 2;
    while (open_fds > 0) {
        const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
        if (left.count() <= 0) {
            r.timed_out = true;
            kill(pid, SIGKILL);
            break;
        }
        const int n = poll(fds, 2, static_cast<int>(left.count()));
        if (n < 0) {
            if (errno == EINTR) continue;
            ADD_FAILURE() << "poll: " << std::strerror(errno);
            kill(pid, SIGKILL);
            break;
        }
        for (int i = 0; i < 2; ++i) {
            if (fds[i].fd < 0 || fds[i].revents == 0) continue;
            char buf[4096];
            const ssize_t got = read(fds[i].fd, buf, sizeof buf);
            if (got > 0) {
                sinks[i]->append(buf, static_cast<std::size_t>(got));
            } else if (got == 0 || (errno != EINTR && errno != EAGAIN)) {
                close(fds[i].fd);
                fds[i].fd = -1;
                --open_fds;
            }
        }
    }
    for (auto& p : fds)
        if (p.fd >= 0) close(p.fd);
    int status = 0;
    while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
    if (WIFEXITED(status)) r.exit_code = WEXITSTATUS(status);
    if (WIFSIGNALED(status)) r.term_signal = WTERMSIG(status);
    return r;
}

// ---------------------------------------------------------------------------------------------
// Scratch directories and files.

class ScratchDir {
public:
    ScratchDir() {
        std::string templ = (fs::temp_directory_path() / "suite-cli-XXXXXX").string();
        if (!mkdtemp(templ.data())) throw std::runtime_error(std::string("mkdtemp: ") + std::strerror(errno));
        path_ = templ;
    }
    ~ScratchDir() {
        std::error_code ec;
        // Make everything writable again (the read-only test chmods a subdirectory) and remove.
        for (auto it = fs::recursive_directory_iterator(path_, ec); !ec && it != fs::recursive_directory_iterator(); it.increment(ec))
            fs::permissions(it->path(), fs::perms::owner_all, fs::perm_options::add, ec);
        fs::remove_all(path_, ec);
    }
    ScratchDir(const ScratchDir&) = delete;
    ScratchDir& operator=(const ScratchDir&) = delete;

    const fs::path& path() const { return path_; }

    // Every path under the directory, relative to it, for "nothing was created" checks.
    std::vector<std::string> entries() const {
        std::vector<std::string> out;
        std::error_code ec;
        for (auto it = fs::recursive_directory_iterator(path_, ec); !ec && it != fs::recursive_directory_iterator(); it.increment(ec))
            out.push_back(fs::relative(it->path(), path_).string());
        return out;
    }

private:
    fs::path path_;
};

std::string read_file(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void write_file(const fs::path& p, const std::string& content) {
    std::ofstream out(p, std::ios::binary | std::ios::trunc);
    out << content;
}

std::string join(const std::vector<std::string>& v, const std::string& sep) {
    std::string out;
    for (const auto& s : v) out += (out.empty() ? "" : sep) + s;
    return out;
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
void expect_usage_error(const RunResult& r, const std::vector<std::string>& expected) {
    ASSERT_FALSE(r.timed_out) << r.describe();
    EXPECT_EQ(r.exit_code, 2) << r.describe();
    EXPECT_TRUE(r.out.empty()) << "a usage error must be found before anything runs or prints\n" << r.describe();
    EXPECT_EQ(r.err.rfind("suite: error: ", 0), 0u) << r.describe();
    ASSERT_FALSE(r.err.empty()) << r.describe();
    EXPECT_EQ(r.err.back(), '\n') << "stderr must end with a newline\n" << r.describe();
    const auto lines = std::count(r.err.begin(), r.err.end(), '\n');
    EXPECT_EQ(lines, 1) << "stderr must be exactly one line\n" << r.describe();
    for (const auto& s : expected) EXPECT_NE(r.err.find(s), std::string::npos) << "stderr lacks \"" << s << "\"\n" << r.describe();
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
        {"UnknownKernelSuggestsAdd", {"--kernel=ad", "--out={tmp}/r.json"}, {"'ad'", "did you mean 'add'?", "copy", "triad", "sin-add", "./suite list"}},
        {"UnknownPatternSuggestsRandom", {"--kernel=add", "--pattern=randm", "--out={tmp}/r.json"}, {"'randm'", "did you mean 'random'?", "sequential", "strided"}},
        {"StridedWithoutStride", {"--kernel=add", "--pattern=strided", "--out={tmp}/r.json"}, {"--pattern=strided", "stride", "strided:8"}},
        {"StridedStrideZero", {"--kernel=add", "--pattern=strided:0", "--out={tmp}/r.json"}, {"strided:0", "positive", "strided:8"}},
        {"StoresNtWithRandomPattern", {"--kernel=add", "--stores=nt", "--pattern=random", "--out={tmp}/r.json"}, {"--stores=nt", "'random'", "sequential"}},
        {"StoresNtWithSinAdd", {"--kernel=sin-add", "--stores=nt", "--out={tmp}/r.json"}, {"--stores=nt", "'sin-add'", "copy, scale, add, triad"}},
        {"StoresBogus", {"--kernel=add", "--stores=bogus", "--out={tmp}/r.json"}, {"'bogus'", "default, nt"}},
        {"OrderingForStreamKernel", {"--kernel=triad", "--ordering=morton", "--out={tmp}/r.json"}, {"'triad'", "--ordering", "--pattern"}},

        // Sizes.
        {"SizeUnknownUnit", {"--kernel=add", "--size=12XB", "--out={tmp}/r.json"}, {"'12XB'", "'XB'", "KiB", "MiB", "GiB", "MB"}},
        {"SizeZero", {"--kernel=add", "--size=0", "--out={tmp}/r.json"}, {"'0'", "at least 1 byte"}},
        {"SizeNegative", {"--kernel=add", "--size=-5MiB", "--out={tmp}/r.json"}, {"'-5MiB'", "positive"}},
        {"SizeLargerThanMemory", {"--kernel=add", "--size=100TiB", "--out={tmp}/r.json"}, {"100TiB", "memory available"}},
        {"SizesSweepBackwards", {"--kernel=add", "--sizes=1GiB:16KiB", "--out={tmp}/r.json"}, {"'1GiB:16KiB'", "first size is larger than the last"}},
        {"SizeAndSizesTogether", {"--kernel=add", "--size=1MiB", "--sizes=1MiB:4MiB", "--out={tmp}/r.json"}, {"--size", "--sizes", "together"}},

        // Threads and pinning.
        {"ThreadsZero", {"--kernel=add", "--threads=0", "--out={tmp}/r.json"}, {"0", "at least 1 thread"}},
        {"ThreadsMoreThanPus", {"--kernel=add", "--threads=999", "--out={tmp}/r.json"}, {"999", "processing units", "at most"}, Needs::fewer_than_999_pus},
        {"ThreadsBackwardsRange", {"--kernel=add", "--threads=4-1", "--out={tmp}/r.json"}, {"'4-1'", "1-8"}},
        {"PinBogus", {"--kernel=add", "--pin=bogus", "--out={tmp}/r.json"}, {"'bogus'", "compact", "scatter", "none", "CPU list"}},
        {"PinCpuDoesNotExist", {"--kernel=add", "--pin=4096", "--out={tmp}/r.json"}, {"CPU 4096", "does not have", "./suite info"}},
        {"PinCpuTwice", {"--kernel=add", "--pin=0,0", "--threads=1", "--out={tmp}/r.json"}, {"CPU 0", "twice"}},

        // Placement.
        {"PlacementNodeDoesNotExist", {"--kernel=add", "--placement=node:7", "--out={tmp}/r.json"}, {"node:7", "no NUMA node 7"}, Needs::fewer_than_8_numa_nodes},
        {"PlacementRemoteOnOneNode", {"--kernel=add", "--placement=remote", "--out={tmp}/r.json"}, {"--placement=remote", "at least 2 NUMA nodes", "local", "interleave"}, Needs::one_numa_node},
        {"PlacementUnknown", {"--kernel=add", "--placement=nowhere", "--out={tmp}/r.json"}, {"'nowhere'", "local", "node:N", "remote", "interleave"}},

        // Repetitions.
        {"RepsZero", {"--kernel=add", "--reps=0", "--out={tmp}/r.json"}, {"--reps=0", "at least 1"}},
        {"RepsNotANumber", {"--kernel=add", "--reps=abc", "--out={tmp}/r.json"}, {"--reps", "abc"}},

        // Output.
        {"OutDirectoryDoesNotExist", {"--kernel=add", "--out={tmp}/nosuchdir/r.json"}, {"nosuchdir", "does not exist"}},
        // Nobody, root included, can create a file directly in /proc. Small sizes keep it quick
        // should the check be missing and the benchmark run.
        {"OutDirectoryNotWritable", {"--kernel=add", "--size=1MiB", "--threads=1", "--reps=1", "--out=/proc/r.json"}, {"/proc/r.json", "not writable"}},
        {"OutIsADirectory", {"--kernel=add", "--out={tmp}"}, {"is a directory", "run.json"}},
        {"FormatXml", {"--kernel=add", "--format=xml", "--out={tmp}/r.json"}, {"'xml'", "table, json, csv"}},
        {"FormatTableToFile", {"--kernel=add", "--format=table", "--out={tmp}/r.txt"}, {"--format=table", "json or csv"}},

        // Options and commands.
        {"UnknownOption", {"--bogus", "--out={tmp}/r.json"}, {"--bogus", "./suite --help"}},
        {"UnknownCommandSuggestsList", {"lsit"}, {"'lsit'", "did you mean 'list'?", "run, list, info"}},
        {"ListUnknownOption", {"list", "--bogus"}, {"--bogus"}},
    };
    return table;
}

class CliErrorTest : public testing::TestWithParam<Case> {};

TEST_P(CliErrorTest, ExitsTwoWithOneLineAndWritesNothing) {
    const Case& c = GetParam();
    const auto& topo = topology();
    switch (c.needs) {
        case Needs::nothing: break;
        case Needs::one_numa_node:
            if (topo.nodes.size() >= 2) GTEST_SKIP() << "this machine has " << topo.nodes.size() << " NUMA nodes; the case needs one";
            break;
        case Needs::fewer_than_8_numa_nodes:
            for (const auto& n : topo.nodes)
                if (n.os_index == 7) GTEST_SKIP() << "this machine has a NUMA node 7";
            break;
        case Needs::fewer_than_999_pus:
            if (topo.pu_count() >= 999) GTEST_SKIP() << "this machine has " << topo.pu_count() << " PUs";
            break;
    }

    ScratchDir dir;
    const auto args = substitute(c.args, dir.path());
    SCOPED_TRACE("suite " + join(args, " "));
    const RunResult r = run_suite(args, dir.path());
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
    ScratchDir dir;
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
        const RunResult r = run_suite(args, dir.path());
        expect_usage_error(r, {});
        EXPECT_EQ(read_file(file), content);
        EXPECT_EQ(fs::last_write_time(file), mtime);
        EXPECT_EQ(dir.entries(), std::vector<std::string>{"r.json"}) << "other files were created";
    }
}

// A directory the user cannot write to (a mode 0555 directory; root ignores the mode bits, so
// this one only runs unprivileged; OutDirectoryNotWritable covers root with /proc).
TEST(CliOutputTest, ReadOnlyDirectoryRefused) {
    if (geteuid() == 0) GTEST_SKIP() << "running as root, which can write into a mode 0555 directory";
    ScratchDir dir;
    const fs::path ro = dir.path() / "ro";
    fs::create_directory(ro);
    fs::permissions(ro, fs::perms::owner_read | fs::perms::owner_exec | fs::perms::group_read | fs::perms::group_exec |
                            fs::perms::others_read | fs::perms::others_exec);
    const RunResult r = run_suite({"--kernel=add", "--size=1MiB", "--threads=1", "--reps=1", "--out=" + (ro / "r.json").string()}, dir.path());
    expect_usage_error(r, {"not writable"});
    EXPECT_TRUE(fs::is_empty(ro));
}

// ---------------------------------------------------------------------------------------------
// The commands that must work.

TEST(CliUsageTest, HelpShowsExamples) {
    ScratchDir dir;
    const RunResult r = run_suite({"--help"}, dir.path());
    ASSERT_FALSE(r.timed_out) << r.describe();
    EXPECT_EQ(r.exit_code, 0) << r.describe();
    EXPECT_NE(r.out.find("Examples:"), std::string::npos) << r.describe();
    EXPECT_NE(r.out.find("--kernel"), std::string::npos) << r.describe();
    EXPECT_TRUE(r.err.empty()) << r.describe();
    EXPECT_TRUE(dir.entries().empty());
}

TEST(CliUsageTest, ListSucceeds) {
    ScratchDir dir;
    const RunResult r = run_suite({"list"}, dir.path());
    ASSERT_FALSE(r.timed_out) << r.describe();
    EXPECT_EQ(r.exit_code, 0) << r.describe();
    for (const char* k : {"copy", "triad", "add", "sin-add", "latency"}) EXPECT_NE(r.out.find(k), std::string::npos) << k << "\n" << r.describe();
    EXPECT_TRUE(dir.entries().empty());
}

TEST(CliUsageTest, InfoSucceeds) {
    ScratchDir dir;
    const RunResult r = run_suite({"info"}, dir.path());
    ASSERT_FALSE(r.timed_out) << r.describe();
    EXPECT_EQ(r.exit_code, 0) << r.describe();
    EXPECT_NE(r.out.find("NUMA"), std::string::npos) << r.describe();
    EXPECT_TRUE(dir.entries().empty());
}

// The helper itself: exit status and streams come back, and a timeout kills the child
// instead of hanging the test.
TEST(CliHarnessTest, RunnerReportsStatusAndKillsOnTimeout) {
    ScratchDir dir;
    const RunResult quick = run_suite({"lsit"}, dir.path());
    EXPECT_FALSE(quick.timed_out);
    EXPECT_EQ(quick.exit_code, 2);
    EXPECT_TRUE(quick.out.empty());
    EXPECT_FALSE(quick.err.empty());

    const RunResult slow = run_suite({"--kernel=add", "--size=64MiB", "--threads=1", "--reps=10000000", "--quiet"}, dir.path(),
                                     std::chrono::milliseconds(1500));
    EXPECT_TRUE(slow.timed_out) << slow.describe();
    EXPECT_EQ(slow.term_signal, SIGKILL) << slow.describe();
    EXPECT_TRUE(dir.entries().empty());
}

}  // namespace
