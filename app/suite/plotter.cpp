#include "app/suite/plotter.hpp"

#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "app/suite/data_dir.hpp"
#include "harness/common/units.hpp"

namespace suite {

Plotter find_plotter(const std::string& script) {
    Plotter p;
    // The script and the modules it imports from beside it.
    for (const std::string& name : {script, std::string("safe_output.py")}) {
        std::string why;
        const std::string path = data_file("plots/" + name, why);
        if (path.empty()) {
            p.reason = why;
            return p;
        }
        if (name == script) p.script = path;
    }
    if (const char* env = std::getenv("SUITE_PYTHON"); env && *env)
        p.python = env;
    else if (access("/usr/bin/python3", X_OK) == 0)
        p.python = "/usr/bin/python3";  // Debian's, which has matplotlib
    else
        p.python = "python3";
    return p;
}

void require_plotter(const std::string& script, const std::string& skip) {
    const Plotter p = find_plotter(script);
    if (!p.reason.empty() && data_dir().installed) throw UsageError(p.reason + "; or give " + skip);
}

std::string draw(const Plotter& p, const std::string& dir) { return draw_with(p, {dir}, dir); }

std::string draw_with(const Plotter& p, const std::vector<std::string>& args, const std::string& scratch_dir) {
    const std::string err_file = scratch_dir + "/.plot-stderr-" + std::to_string(getpid());
    std::fflush(nullptr);  // or the child would write out its copy of what is still buffered
    const pid_t pid = fork();
    if (pid < 0) return std::string("fork failed: ") + std::strerror(errno);
    if (pid == 0) {
        if (!std::freopen(err_file.c_str(), "w", stderr) || !std::freopen("/dev/null", "w", stdout)) _exit(126);
        std::vector<char*> argv{const_cast<char*>(p.python.c_str()), const_cast<char*>(p.script.c_str())};
        for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
        argv.push_back(nullptr);
        execvp(p.python.c_str(), argv.data());
        std::fprintf(stderr, "cannot run %s: %s\n", p.python.c_str(), std::strerror(errno));
        _exit(127);
    }
    int status = 0;
    while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
    std::string last;
    if (FILE* f = std::fopen(err_file.c_str(), "r")) {
        char line[512];
        while (std::fgets(line, sizeof line, f))
            if (line[0] != '\n') last = line;
        std::fclose(f);
    }
    unlink(err_file.c_str());
    while (!last.empty() && last.back() == '\n') last.pop_back();
    if (WIFEXITED(status) && WEXITSTATUS(status) == 0) return "";
    return last.empty() ? "the plot script failed (status " + std::to_string(status) + ")" : last;
}

}  // namespace suite
