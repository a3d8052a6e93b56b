// OutputDir: a directory that holds one run's files (output_file.hpp has the policy). Nothing
// here removes a file it cannot show to be a suite run's: one listed in the directory's
// manifest, a temporary file of the suite's own naming in a directory that has a manifest, or
// what is inside a staging directory this code made (a real directory, never followed through
// a symlink).
#include <dirent.h>
#include <fcntl.h>
#include <ftw.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <fstream>
#include <regex>
#include <set>
#include <stdexcept>

#include "harness/common/output_detail.hpp"
#include "harness/common/output_file.hpp"
#include "harness/common/sysfs_file.hpp"  // file_kind
#include "harness/common/units.hpp"

namespace suite {

namespace {

using output_detail::errno_text;

const char* const lock_name = ".suite.lock";
const char* const manifest_name = ".suite-files";
const std::string staging_prefix = ".suite-new.";
// An interrupted replacement's files, kept beside the earlier complete set they did not replace.
const char* const incomplete_name = ".suite-incomplete";

bool is_real_directory(const std::string& path) {
    struct stat st {};
    return lstat(path.c_str(), &st) == 0 && S_ISDIR(st.st_mode);
}

// A staging directory of this code's naming: `.suite-new.PID` or an interrupted run's kept
// `.suite-incomplete`, and a real directory. The next claim of the directory removes them.
bool is_staging(const std::string& dir, const std::string& name) {
    static const std::regex pattern(R"(\.suite-new\.[0-9]+|\.suite-incomplete)");
    return std::regex_match(name, pattern) && is_real_directory(dir + "/" + name);
}

// What the suite's writers leave behind when a process dies mid-write: FILE.tmp.PID and
// FILE.probe.PID (output_file.cpp), .plot-stderr (the plotter). The suite's only in a directory
// that has a manifest.
bool is_leftover(const std::string& name) {
    static const std::regex pattern(R"(.+\.(tmp|probe)\.[0-9]+|\.plot-stderr)");
    return std::regex_match(name, pattern);
}

// Every entry of `dir` but ".", "..", the lock, the manifest and staging directories, sorted.
// Throws UsageError when the directory cannot be listed: an unreadable directory is not empty.
std::vector<std::string> entries(const std::string& dir, const std::string& option) {
    std::vector<std::string> out;
    DIR* d = opendir(dir.c_str());
    if (!d)
        throw UsageError(option + "=" + dir + ": cannot list what the directory holds (" + errno_text(errno) +
                         "); it must be readable");
    while (const dirent* e = readdir(d)) {
        const std::string name = e->d_name;
        if (name == "." || name == ".." || name == lock_name || name == manifest_name || is_staging(dir, name))
            continue;
        out.push_back(name);
    }
    closedir(d);
    std::sort(out.begin(), out.end());
    return out;
}

// The manifest: the command that wrote the files, and their names.
struct Manifest {
    bool found = false;
    std::string command;
    std::set<std::string> files;
};

Manifest read_manifest(const std::string& dir) {
    Manifest m;
    std::ifstream in(dir + "/" + manifest_name);
    if (!in) return m;
    m.found = true;
    std::getline(in, m.command);
    for (std::string line; std::getline(in, line);)
        if (!line.empty()) m.files.insert(line);
    return m;
}

std::string manifest_text(const std::string& command, const std::set<std::string>& files) {
    std::string text = (command.empty() ? "suite" : command) + "\n";
    for (const auto& f : files) text += f + "\n";
    return text;
}

std::string some(const std::vector<std::string>& names) {
    std::string out;
    for (std::size_t i = 0; i < names.size() && i < 3; ++i) out += (i ? ", " : "") + names[i];
    if (names.size() > 3) out += ", ...";
    return out;
}

// Removes a staging directory and everything in it, never following a symlink out of it.
void remove_tree(const std::string& path) noexcept {
    if (!is_real_directory(path)) return;
    nftw(
        path.c_str(),
        [](const char* p, const struct stat*, int type, struct FTW*) {
            if (type == FTW_DP)
                rmdir(p);
            else
                unlink(p);
            return 0;
        },
        16, FTW_DEPTH | FTW_PHYS);
}

// "out/" and "out" are the same directory; lstat("link/") would follow the link.
std::string without_trailing_slashes(std::string dir) {
    while (dir.size() > 1 && dir.back() == '/') dir.pop_back();
    return dir;
}

// The directory itself: a directory (never a symlink to one), or a new name in an existing
// one; with `create`, made when missing.
void check_dir_itself(const std::string& dir, const std::string& option, bool create) {
    if (dir.empty())
        throw UsageError(option + " is empty; give a directory for the files, e.g. " + option + "=results/out");
    struct stat st {};
    if (lstat(dir.c_str(), &st) == 0) {
        if (S_ISLNK(st.st_mode))
            throw UsageError(option + "=" + dir +
                             " is a symlink; the suite writes no output through a symlink: give the directory itself");
        if (!S_ISDIR(st.st_mode))
            throw UsageError(option + "=" + dir + " exists and is " + file_kind(st.st_mode) + ", not a directory; " +
                             option + " names a directory for several files");
        if (faccessat(AT_FDCWD, dir.c_str(), R_OK | W_OK | X_OK, AT_EACCESS) != 0)
            throw UsageError(option + "=" + dir + ": the directory is not readable and writable by this user (" +
                             errno_text(errno) + ")");
        return;
    }
    const std::string parent = output_detail::parent_of(dir);
    if (stat(parent.c_str(), &st) != 0 || !S_ISDIR(st.st_mode))
        throw UsageError(option + "=" + dir + ": the directory '" + parent + "' does not exist");
    if (create && mkdir(dir.c_str(), 0755) != 0 && errno != EEXIST)
        throw UsageError(option + "=" + dir + ": cannot create it (" + errno_text(errno) + ")");
}

// What the directory holds, against the policy; returns the earlier run's files (to replace).
std::vector<std::string> check_contents(const std::string& dir, const DirPolicy& p) {
    const std::vector<std::string> present = entries(dir, p.option);
    if (present.empty()) return {};
    const Manifest m = read_manifest(dir);
    std::vector<std::string> unknown;
    for (const auto& name : present)
        if (!m.files.count(name) && !(m.found && is_leftover(name))) unknown.push_back(name);
    const std::string where = p.option + "=" + dir;
    if (!unknown.empty())
        throw UsageError(where + " holds " + std::to_string(unknown.size()) + " file(s) the suite did not write (" +
                         some(unknown) +
                         "); give a new or empty directory (only an earlier run's own files are ever replaced)");
    for (const auto& name : present) {
        struct stat st {};
        const std::string path = dir + "/" + name;
        if (lstat(path.c_str(), &st) == 0 && !S_ISREG(st.st_mode))
            throw UsageError(where + ": " + name + " is " + file_kind(st.st_mode) +
                             " where a run's file was; remove it");
        for (const auto& in : p.inputs)
            if (in.dev == st.st_dev && in.ino == st.st_ino)
                throw UsageError(where + ": " + name + " is the input " + in.path +
                                 "; replacing the directory's files would destroy it");
    }
    if (!p.replace_earlier) {
        const std::string who = m.command.empty() ? "suite" : m.command;
        throw UsageError(where + " holds the files of an earlier `" + who + "` run (" + std::to_string(present.size()) +
                         " file(s): " + some(present) +
                         "); give --replace to replace them all, or a new or empty directory");
    }
    return present;
}

// A command's fixed files (history html): each, where it exists, a regular file.
void check_fixed(const std::string& dir, const DirPolicy& p) {
    for (const auto& name : p.fixed_files) {
        struct stat st {};
        if (lstat((dir + "/" + name).c_str(), &st) == 0 && !S_ISREG(st.st_mode))
            throw UsageError(p.option + "=" + dir + ": " + name + " is " + file_kind(st.st_mode) +
                             ", where this command writes a file; remove it");
    }
}

}  // namespace

void OutputDir::check(const std::string& given, const DirPolicy& policy) {
    const std::string dir = without_trailing_slashes(given);
    check_dir_itself(dir, policy.option, false);
    if (!is_real_directory(dir)) return;
    if (policy.fixed_files.empty())
        check_contents(dir, policy);
    else
        check_fixed(dir, policy);
}

OutputDir OutputDir::claim(const std::string& given, const DirPolicy& policy) {
    const std::string dir = without_trailing_slashes(given);
    check_dir_itself(dir, policy.option, true);
    OutputDir d;
    d.dir_ = dir;
    d.policy_ = policy;
    d.lock_ =
        OutputLock(dir + "/" + lock_name, output_detail::take_lock(dir + "/" + lock_name, policy.option + "=" + dir));
    d.writing_ = dir;
    if (!policy.fixed_files.empty()) {
        check_fixed(dir, policy);
        d.committed_ = true;  // nothing to swap or list: each file is replaced where it is
        d.claimed_ = true;
        return d;
    }
    d.earlier_ = check_contents(dir, policy);  // a refusal drops the lock with d
    // Held, and the directory is the suite's: a staging directory left in it is a dead run's.
    if (DIR* h = opendir(dir.c_str())) {
        std::vector<std::string> stale;
        while (const dirent* e = readdir(h))
            if (is_staging(dir, e->d_name)) stale.push_back(dir + "/" + e->d_name);
        closedir(h);
        for (const auto& s : stale) remove_tree(s);
    }
    if (!d.earlier_.empty()) {
        d.staging_ = true;
        d.writing_ = dir + "/" + staging_prefix + std::to_string(getpid());
        if (mkdir(d.writing_.c_str(), 0755) != 0)
            throw UsageError(policy.option + "=" + dir + ": cannot create the staging directory " + d.writing_ + " (" +
                             errno_text(errno) + ")");
    } else {
        // Straight into the directory: the manifest names each file as it is written, so that
        // even a run that is killed leaves files a later --replace knows as its own.
        output_detail::replace_file(dir + "/" + manifest_name, manifest_text(policy.command, {}));
    }
    d.claimed_ = true;
    return d;
}

OutputDir& OutputDir::operator=(OutputDir&& other) noexcept {
    if (this != &other) {
        release();
        dir_ = std::move(other.dir_);
        writing_ = std::move(other.writing_);
        policy_ = std::move(other.policy_);
        earlier_ = std::move(other.earlier_);
        written_ = std::move(other.written_);
        staging_ = other.staging_;
        committed_ = other.committed_;
        claimed_ = other.claimed_;
        lock_ = std::move(other.lock_);
    }
    return *this;
}

void OutputDir::record(const std::string& name) {
    if (!written_.insert(name).second || staging_ || !policy_.fixed_files.empty()) return;
    const std::string path = dir_ + "/" + manifest_name;
    const int fd = open(path.c_str(), O_WRONLY | O_APPEND | O_CLOEXEC | O_NOFOLLOW);
    if (fd < 0) return;
    const std::string line = name + "\n";
    (void)!::write(fd, line.data(), line.size());
    close(fd);
}

void OutputDir::write(const std::string& name, const std::string& content) {
    if (!lock_.held()) throw std::logic_error("OutputDir::write on a directory that was not claimed");
    if (name.empty() || name.find('/') != std::string::npos || name == "." || name == ".." || name == lock_name ||
        name == manifest_name || name.rfind(staging_prefix, 0) == 0)
        throw std::logic_error("OutputDir::write: '" + name + "' is not a plain file name of an output");
    if (!policy_.fixed_files.empty() &&
        std::find(policy_.fixed_files.begin(), policy_.fixed_files.end(), name) == policy_.fixed_files.end())
        throw std::logic_error("OutputDir::write: '" + name + "' is not one of the files this command declared");
    output_detail::check_target(writing_ + "/" + name, policy_.option, policy_.inputs, false);
    output_detail::replace_file(writing_ + "/" + name, content);
    record(name);
}

std::string OutputDir::with_writer(const std::function<std::string(const std::string& dir)>& writer) {
    const std::vector<std::string> before = entries(writing_, policy_.option);
    const std::string result = writer(writing_);
    for (const auto& name : entries(writing_, policy_.option))
        if (!std::binary_search(before.begin(), before.end(), name) && !is_leftover(name)) record(name);
    return result;
}

void OutputDir::commit() {
    if (!lock_.held() || committed_) return;
    if (staging_) {
        // This run's files over the earlier ones first (each rename replaces atomically), then
        // the earlier names this run did not write, then the manifest. A failure part way keeps
        // the staging directory (what was not moved yet is still there) and lists every file
        // the directory may now hold, earlier or new, so that a later --replace takes them all.
        std::set<std::string> moved;
        try {
            for (const auto& name : entries(writing_, policy_.option)) {
                if (rename((writing_ + "/" + name).c_str(), (dir_ + "/" + name).c_str()) != 0)
                    throw std::runtime_error("cannot move " + name + " into " + dir_ + ": " + errno_text(errno));
                moved.insert(name);
            }
            for (const auto& name : earlier_)
                if (!moved.count(name) && unlink((dir_ + "/" + name).c_str()) != 0 && errno != ENOENT)
                    throw std::runtime_error("cannot remove " + dir_ + "/" + name +
                                             " of the earlier run: " + errno_text(errno));
        } catch (const std::runtime_error& e) {
            std::set<std::string> all(earlier_.begin(), earlier_.end());
            all.insert(moved.begin(), moved.end());
            try {
                output_detail::replace_file(dir_ + "/" + manifest_name, manifest_text(policy_.command, all));
            } catch (...) {
            }
            committed_ = true;  // nothing more to undo: release() must not remove the staging directory
            throw std::runtime_error(std::string(e.what()) + "; the files not moved are in " + writing_);
        }
        written_ = std::move(moved);
        output_detail::replace_file(dir_ + "/" + manifest_name, manifest_text(policy_.command, written_));
        rmdir(writing_.c_str());
    } else {
        output_detail::replace_file(dir_ + "/" + manifest_name, manifest_text(policy_.command, written_));
    }
    committed_ = true;
}

std::string OutputDir::keep_incomplete() {
    if (!lock_.held() || committed_ || !staging_) return "";
    const std::string kept = dir_ + "/" + incomplete_name;
    remove_tree(kept);
    if (rename(writing_.c_str(), kept.c_str()) != 0)
        throw std::runtime_error("cannot keep the interrupted run's files as " + kept + ": " + errno_text(errno) +
                                 "; they are in " + writing_);
    committed_ = true;  // the earlier set stays; nothing of this run's is to be removed
    return kept;
}

void OutputDir::release() noexcept {
    if (!lock_.held()) return;
    if (claimed_ && !committed_) {
        if (staging_) {
            remove_tree(writing_);  // the earlier run's files stay as they were
        } else {
            try {  // what was written is this run's: listed, so that --replace may take it later
                output_detail::replace_file(dir_ + "/" + manifest_name, manifest_text(policy_.command, written_));
            } catch (...) {
            }
        }
    }
    lock_.release();
}

}  // namespace suite
