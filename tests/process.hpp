#pragma once
// Runs the real suite binary (and other programs) for end-to-end tests: no shell, arguments as
// given, default signal dispositions, stdin from /dev/null, stdout and stderr captured, a time
// limit; plus scratch directories and small file helpers. Header-only so each test file can include it.
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <stdlib.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <system_error>
#include <vector>

namespace suite::test {

// How a finished program ended and what it wrote to stdout and stderr.
struct Outcome {
    int status = -1;         // exit status, or 128+signal if killed
    int term_signal = 0;     // the signal that ended it, 0 if it exited
    bool timed_out = false;  // killed by finish() because the time limit ran out
    std::string out, err;

    // Both streams, stdout first, for checks that do not care which one a line went to.
    std::string combined() const { return out + err; }
};

// The exit status, how it ended and both streams, for failure messages.
inline std::string describe(const Outcome& r) {
    std::ostringstream s;
    s << "exit status " << r.status;
    if (r.term_signal) s << ", killed by signal " << r.term_signal;
    if (r.timed_out) s << " (timed out)";
    s << "\n--- stdout ---\n" << r.out << "\n--- stderr ---\n" << r.err << "\n---";
    return s.str();
}

// Starts `argv` (argv[0] is the program path) in directory `cwd` ("" = this one), stdin from
// /dev/null; returns the pid and the read ends of its stdout and stderr pipes.
inline pid_t spawn(const std::vector<std::string>& argv, int& out_fd, int& err_fd, const std::string& cwd = "") {
    int o[2], e[2];
    if (pipe2(o, O_CLOEXEC) != 0) throw std::system_error(errno, std::generic_category(), "pipe2");
    if (pipe2(e, O_CLOEXEC) != 0) {
        const int saved = errno;
        close(o[0]);
        close(o[1]);
        throw std::system_error(saved, std::generic_category(), "pipe2");
    }
    // Under user-mode emulation (the aarch64 tests on an x86-64 host, make test-arm64) the suite
    // binary runs under the emulator SUITE_TEST_EMULATOR names; other programs (python3, objdump)
    // are the host's own.
    std::vector<std::string> command = argv;
#ifdef SUITE_BINARY
    if (const char* emulator = std::getenv("SUITE_TEST_EMULATOR");
        emulator && *emulator && !argv.empty() && argv[0] == SUITE_BINARY)
        command.insert(command.begin(), emulator);
#endif
    std::vector<char*> args;
    for (const auto& a : command) args.push_back(const_cast<char*>(a.c_str()));
    args.push_back(nullptr);
    const pid_t pid = fork();
    if (pid < 0) {
        const int saved = errno;
        close(o[0]);
        close(o[1]);
        close(e[0]);
        close(e[1]);
        throw std::system_error(saved, std::generic_category(), "fork");
    }
    if (pid == 0) {
        // Child: only async-signal-safe calls from here on. dup2 clears O_CLOEXEC on 0, 1, 2.
        // The program starts as a user's shell starts it: every signal at its default action
        // and none blocked, whatever the test runner set (a runner that ignores SIGXFSZ or
        // SIGPIPE would otherwise hide how the program behaves on its own).
        for (int sig = 1; sig < NSIG; ++sig) signal(sig, SIG_DFL);
        sigset_t none;
        sigemptyset(&none);
        sigprocmask(SIG_SETMASK, &none, nullptr);
        const int devnull = open("/dev/null", O_RDONLY | O_CLOEXEC);
        if (devnull >= 0) dup2(devnull, STDIN_FILENO);
        dup2(o[1], STDOUT_FILENO);
        dup2(e[1], STDERR_FILENO);
        if (!cwd.empty() && chdir(cwd.c_str()) != 0) _exit(126);
        execv(args[0], args.data());
        const char msg[] = "process.hpp: execv failed\n";
        (void)!write(STDERR_FILENO, msg, sizeof msg - 1);
        _exit(127);
    }
    close(o[1]);
    close(e[1]);
    out_fd = o[0];
    err_fd = e[0];
    return pid;
}

// Reads both pipes until the process ends and reaps it; kills it (timed_out) after `timeout_s`.
inline Outcome finish(pid_t pid, int out_fd, int err_fd, double timeout_s = 300) {
    using clock = std::chrono::steady_clock;
    Outcome r;
    const auto deadline =
        clock::now() + std::chrono::duration_cast<clock::duration>(std::chrono::duration<double>(timeout_s));
    pollfd fds[2] = {{out_fd, POLLIN, 0}, {err_fd, POLLIN, 0}};
    std::string* sinks[2] = {&r.out, &r.err};
    int open_fds = 2, poll_errno = 0;
    while (open_fds > 0) {
        const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - clock::now()).count();
        if (left <= 0) {
            r.timed_out = true;
            kill(pid, SIGKILL);
            break;
        }
        if (poll(fds, 2, static_cast<int>(std::min<long long>(left, 60'000))) < 0) {  // capped to fit an int
            if (errno == EINTR) continue;
            poll_errno = errno;
            kill(pid, SIGKILL);
            break;
        }
        for (int k = 0; k < 2; ++k) {
            if (fds[k].fd < 0 || fds[k].revents == 0) continue;
            char buf[4096];
            const ssize_t n = read(fds[k].fd, buf, sizeof buf);
            if (n > 0) {
                sinks[k]->append(buf, static_cast<std::size_t>(n));
            } else if (n == 0 || (errno != EINTR && errno != EAGAIN)) {
                close(fds[k].fd);
                fds[k].fd = -1;
                --open_fds;
            }
        }
    }
    for (auto& f : fds)
        if (f.fd >= 0) close(f.fd);
    int st = 0;
    while (waitpid(pid, &st, 0) < 0 && errno == EINTR) {
    }
    if (poll_errno) throw std::system_error(poll_errno, std::generic_category(), "poll");
    if (WIFSIGNALED(st)) r.term_signal = WTERMSIG(st);
    r.status = WIFEXITED(st) ? WEXITSTATUS(st) : 128 + r.term_signal;
    return r;
}

// Runs `argv` (argv[0] is the program path) to completion in `cwd` ("" = this directory).
inline Outcome run_program(const std::vector<std::string>& argv, double timeout_s = 300, const std::string& cwd = "") {
    int o, e;
    const pid_t pid = spawn(argv, o, e, cwd);
    return finish(pid, o, e, timeout_s);
}

// Runs the suite binary with `args` (its argv[1..]) to completion in `cwd` ("" = this directory).
inline Outcome run_suite(const std::vector<std::string>& args, double timeout_s = 300, const std::string& cwd = "") {
    std::vector<std::string> argv{SUITE_BINARY};
    argv.insert(argv.end(), args.begin(), args.end());
    return run_program(argv, timeout_s, cwd);
}

// Creates a fresh directory /tmp/suite-test-XXXXXX that the caller must remove.
inline std::string make_temp_dir() {
    char tmpl[] = "/tmp/suite-test-XXXXXX";
    if (!mkdtemp(tmpl)) throw std::system_error(errno, std::generic_category(), "mkdtemp");
    return tmpl;
}

// A fresh directory under $TMPDIR (or /tmp), removed with everything in it when it goes out of scope.
class TempDir {
public:
    TempDir() {
        std::string templ = (std::filesystem::temp_directory_path() / "suite-test-XXXXXX").string();
        if (!mkdtemp(templ.data())) throw std::system_error(errno, std::generic_category(), "mkdtemp");
        path_ = templ;
    }
    ~TempDir() {
        namespace fs = std::filesystem;
        std::error_code ec;
        // Make everything writable again first (a test may chmod a subdirectory read-only).
        for (auto it = fs::recursive_directory_iterator(path_, ec); !ec && it != fs::recursive_directory_iterator();
             it.increment(ec))
            fs::permissions(it->path(), fs::perms::owner_all, fs::perm_options::add, ec);
        fs::remove_all(path_, ec);
    }
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;

    // True while the directory exists.
    bool ok() const { return std::filesystem::is_directory(path_); }
    // The directory itself.
    const std::filesystem::path& path() const { return path_; }
    // The path of `name` inside the directory.
    std::string file(const std::string& name) const { return (path_ / name).string(); }
    // Every path under the directory, relative to it, for "nothing was created" checks.
    std::vector<std::string> entries() const {
        namespace fs = std::filesystem;
        std::vector<std::string> out;
        std::error_code ec;
        for (auto it = fs::recursive_directory_iterator(path_, ec); !ec && it != fs::recursive_directory_iterator();
             it.increment(ec))
            out.push_back(fs::relative(it->path(), path_).string());
        return out;
    }

private:
    std::filesystem::path path_;
};

// The whole content of the file at `path`, byte for byte ("" if it cannot be read).
// The names in a directory, sorted.
inline std::vector<std::string> names_in(const std::string& dir) {
    std::vector<std::string> out;
    for (const auto& e : std::filesystem::directory_iterator(dir)) out.push_back(e.path().filename().string());
    std::sort(out.begin(), out.end());
    return out;
}

inline std::string slurp(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

// The strings of `v` with `sep` between them, e.g. a command line for a failure message.
inline std::string join(const std::vector<std::string>& v, const std::string& sep = " ") {
    std::string s;
    for (const auto& a : v) s += (s.empty() ? "" : sep) + a;
    return s;
}

// The published result schema of the files the suite writes, the folder of every version's
// (v1.json for the files it still reads), and the script that checks files against them.
inline const std::string schema_path = std::string(SUITE_SOURCE_DIR) + "/results/schema/v2.json";
inline const std::string schema_dir = std::string(SUITE_SOURCE_DIR) + "/results/schema";
inline const std::string validator_path = std::string(SUITE_SOURCE_DIR) + "/tests/validate_result.py";

// Validates result files against results/schema/vN.json, N each file's schema_version, with
// Debian's python3-jsonschema.
inline Outcome validate_against_schema(const std::vector<std::string>& files, double timeout_s = 60) {
    std::vector<std::string> argv{SUITE_PYTHON, validator_path, schema_dir};
    argv.insert(argv.end(), files.begin(), files.end());
    return run_program(argv, timeout_s);
}

// Validates one result file against the schema of its version.
inline Outcome validate_against_schema(const std::string& file) {
    return validate_against_schema(std::vector<std::string>{file});
}

// Validates files the suite wrote, each against the schema of its own kind (a run's result,
// a roofline file, a placement: tests/validate_result.py --by-kind).
inline Outcome validate_by_kind(const std::vector<std::string>& files, double timeout_s = 60) {
    std::vector<std::string> argv{SUITE_PYTHON, validator_path, "--by-kind",
                                  std::string(SUITE_SOURCE_DIR) + "/results/schema"};
    argv.insert(argv.end(), files.begin(), files.end());
    return run_program(argv, timeout_s);
}

}  // namespace suite::test
