#include "app/suite/data_dir.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <climits>

#include "harness/results/build_info.hpp"

namespace suite {

namespace {

bool is_directory(const std::string& path) {
    struct stat st {};
    return stat(path.c_str(), &st) == 0 && S_ISDIR(st.st_mode);
}

std::string program_directory() {
    char buf[PATH_MAX];
    const ssize_t n = readlink("/proc/self/exe", buf, sizeof buf - 1);
    if (n <= 0) return "";
    std::string exe(buf, static_cast<std::size_t>(n));
    const auto slash = exe.rfind('/');
    return slash == std::string::npos ? "" : exe.substr(0, slash);
}

}  // namespace

const DataDir& data_dir() {
    static const DataDir d = [] {
        DataDir out;
        const std::string bin = program_directory();
        const std::string share = bin.empty() ? "" : bin + "/../share/suite";
        if (!share.empty() && is_directory(share)) {
            out.path = share;
            out.installed = true;
        } else {
            out.path = SUITE_SOURCE_TREE;
        }
        return out;
    }();
    return d;
}

std::string data_file(const std::string& relative, std::string& why) {
    const DataDir& d = data_dir();
    const std::string path = d.path + "/" + relative;
    if (access(path.c_str(), R_OK) == 0) return path;
    why = d.installed ? path + " is missing from the installed tree (looked in " + d.path +
                            ", beside this program's bin/); reinstall the suite"
                      : path +
                            " is not readable (the source tree this suite was built from has moved; install it with "
                            "make install PREFIX=...)";
    return "";
}

std::string version_text(const std::string& program) {
    std::string t = program + " " + build::version + " (git " + build::git_revision + ")\n";
    t += "compiler: " + std::string(build::compiler) + ", " + build::build_type + ", flags: " + build::flags + "\n";
    t += "built with: " + std::string(build::parts) + "\n";
    const DataDir& d = data_dir();
    t += "data: " + d.path + (d.installed ? " (installed)" : " (the source tree)") + "\n";
    return t;
}

}  // namespace suite
