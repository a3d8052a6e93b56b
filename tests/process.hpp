#pragma once
// Runs the real suite binary for end-to-end tests: no shell, arguments as given, stdout and
// stderr captured, a time limit. Header-only so each test file can include it.
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace suite::test {

struct Outcome {
    int status = -1;  // exit status, or 128+signal if killed
    std::string out, err;
};

// Starts `argv` (argv[0] is the program path) in directory `cwd` ("" = this one), stdin from
// /dev/null; returns the pid and the read ends of its stdout and stderr pipes.
inline pid_t spawn(const std::vector<std::string>& argv, int& out_fd, int& err_fd, const std::string& cwd = "") {
    int o[2], e[2];
    if (pipe(o) != 0 || pipe(e) != 0) throw std::runtime_error("pipe failed");
    pid_t pid = fork();
    if (pid == 0) {
        if (!cwd.empty() && chdir(cwd.c_str()) != 0) _exit(126);
        int devnull = open("/dev/null", O_RDONLY);
        if (devnull >= 0) dup2(devnull, 0);
        dup2(o[1], 1);
        dup2(e[1], 2);
        close(o[0]); close(o[1]); close(e[0]); close(e[1]);
        std::vector<char*> args;
        for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
        args.push_back(nullptr);
        execv(args[0], args.data());
        _exit(127);
    }
    close(o[1]);
    close(e[1]);
    out_fd = o[0];
    err_fd = e[0];
    return pid;
}

// Reads both pipes until the process ends; kills it after `timeout_s`.
inline Outcome finish(pid_t pid, int out_fd, int err_fd, double timeout_s = 300) {
    Outcome r;
    auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
    pollfd fds[2] = {{out_fd, POLLIN, 0}, {err_fd, POLLIN, 0}};
    int open_fds = 2;
    char buf[4096];
    while (open_fds > 0) {
        if (std::chrono::steady_clock::now() > deadline) { kill(pid, SIGKILL); break; }
        if (poll(fds, 2, 100) <= 0) continue;
        for (int k = 0; k < 2; ++k) {
            if (fds[k].fd < 0 || !(fds[k].revents & (POLLIN | POLLHUP))) continue;
            ssize_t n = read(fds[k].fd, buf, sizeof buf);
            if (n <= 0) { close(fds[k].fd); fds[k].fd = -1; --open_fds; continue; }
            (k == 0 ? r.out : r.err).append(buf, static_cast<std::size_t>(n));
        }
    }
    for (auto& f : fds)
        if (f.fd >= 0) close(f.fd);
    int st = 0;
    waitpid(pid, &st, 0);
    r.status = WIFEXITED(st) ? WEXITSTATUS(st) : 128 + WTERMSIG(st);
    return r;
}

// Runs the suite binary with `args` to completion, in `cwd` ("" = this directory).
inline Outcome run_suite(const std::vector<std::string>& args, double timeout_s = 300, const std::string& cwd = "") {
    std::vector<std::string> argv{SUITE_BINARY};
    argv.insert(argv.end(), args.begin(), args.end());
    int o, e;
    pid_t pid = spawn(argv, o, e, cwd);
    return finish(pid, o, e, timeout_s);
}

inline std::string make_temp_dir() {
    char tmpl[] = "/tmp/suite-test-XXXXXX";
    if (!mkdtemp(tmpl)) throw std::runtime_error("mkdtemp failed");
    return tmpl;
}

inline std::string slurp(const std::string& path) {
    std::ifstream in(path);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

// Validates a result file against results/schema/v1.json with Debian's python3-jsonschema.
inline Outcome validate_against_schema(const std::string& file) {
    std::vector<std::string> argv{SUITE_PYTHON, std::string(SUITE_SOURCE_DIR) + "/tests/validate_result.py",
                                  std::string(SUITE_SOURCE_DIR) + "/results/schema/v1.json", file};
    int o, e;
    pid_t pid = spawn(argv, o, e);
    return finish(pid, o, e, 60);
}

}  // namespace suite::test
