// OutputDir: a directory that holds one run's files (output_file.hpp has the policy).
#include <dirent.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <fstream>
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

// The directory's own bookkeeping, never a run's output.
bool bookkeeping(const std::string& name) {
    return name == lock_name || name == manifest_name || name.rfind(staging_prefix, 0) == 0;
}

// Every entry of `dir` but "." and ".." (and the bookkeeping unless `all`), sorted.
std::vector<std::string> entries(const std::string& dir, bool all = false) {
    std::vector<std::string> out;
    DIR* d = opendir(dir.c_str());
    if (!d) return out;
    while (const dirent* e = readdir(d)) {
        const std::string name = e->d_name;
        if (name == "." || name == ".." || (!all && bookkeeping(name))) continue;
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

std::string manifest_text(const std::string& command, const std::vector<std::string>& files) {
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

// Removes `path` and what it holds (a staging directory: plain files only).
void remove_tree(const std::string& path) {
    for (const auto& name : entries(path, true)) unlink((path + "/" + name).c_str());
    rmdir(path.c_str());
}

// The directory itself: a directory (never a symlink to one), or a new name in an existing
// one; with `create`, made when missing.
void check_dir_itself(const std::string& dir, const std::string& option, bool create) {
    if (dir.empty()) throw UsageError(option + " is empty; give a directory for the files, e.g. " + option + "=results/out");
    struct stat st{};
    if (lstat(dir.c_str(), &st) == 0) {
        if (S_ISLNK(st.st_mode))
            throw UsageError(option + "=" + dir + " is a symlink; the suite writes no output through a symlink: give the directory itself");
        if (!S_ISDIR(st.st_mode))
            throw UsageError(option + "=" + dir + " exists and is " + file_kind(st.st_mode) + ", not a directory; " + option +
                             " names a directory for several files");
        if (faccessat(AT_FDCWD, dir.c_str(), W_OK | X_OK, AT_EACCESS) != 0)
            throw UsageError(option + "=" + dir + ": the directory is not writable by this user (" + errno_text(errno) + ")");
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
    const std::vector<std::string> present = entries(dir);
    if (present.empty()) return {};
    const Manifest m = read_manifest(dir);
    std::vector<std::string> unknown;
    for (const auto& name : present)
        if (!m.files.count(name)) unknown.push_back(name);
    const std::string where = p.option + "=" + dir;
    if (!unknown.empty())
        throw UsageError(where + " holds " + std::to_string(unknown.size()) + " file(s) the suite did not write (" + some(unknown) +
                         "); give a new or empty directory (only an earlier run's own files are ever replaced)");
    for (const auto& name : present) {
        struct stat st{};
        const std::string path = dir + "/" + name;
        if (lstat(path.c_str(), &st) == 0 && !S_ISREG(st.st_mode))
            throw UsageError(where + ": " + name + " is " + file_kind(st.st_mode) + " where a run's file was; remove it");
        for (const auto& in : p.inputs)
            if (lstat(path.c_str(), &st) == 0 && in.dev == st.st_dev && in.ino == st.st_ino)
                throw UsageError(where + ": " + name + " is the input " + in.path + "; replacing the directory's files would destroy it");
    }
    if (!p.replace_earlier) {
        const std::string who = m.command.empty() ? "suite" : m.command;
        throw UsageError(where + " holds the files of an earlier `" + who + "` run (" + std::to_string(present.size()) + " file(s): " + some(present) +
                         "); give --replace to replace them all, or a new or empty directory");
    }
    return present;
}

}  // namespace

void OutputDir::check(const std::string& dir, const DirPolicy& policy) {
    check_dir_itself(dir, policy.option, false);
    struct stat st{};
    if (policy.fixed_files.empty() && stat(dir.c_str(), &st) == 0) check_contents(dir, policy);
}

OutputDir OutputDir::claim(const std::string& dir, const DirPolicy& policy) {
    check_dir_itself(dir, policy.option, true);
    OutputDir d;
    d.dir_ = dir;
    d.policy_ = policy;
    d.command_ = policy.command;
    d.lock_ = OutputLock(dir + "/" + lock_name, output_detail::take_lock(dir + "/" + lock_name, policy.option + "=" + dir));
    // Held: a staging directory left here is a dead run's, never anyone's work in progress.
    for (const auto& name : entries(dir, true))
        if (name.rfind(staging_prefix, 0) == 0) remove_tree(dir + "/" + name);
    d.writing_ = dir;
    if (!policy.fixed_files.empty()) {
        d.committed_ = true;  // nothing to swap or list: each file is replaced where it is
        d.claimed_ = true;
        return d;
    }
    d.earlier_ = check_contents(dir, policy);  // a refusal drops the lock with d
    if (!d.earlier_.empty()) {
        d.staging_ = true;
        d.writing_ = dir + "/" + staging_prefix + std::to_string(getpid());
        if (mkdir(d.writing_.c_str(), 0755) != 0)
            throw UsageError(policy.option + "=" + dir + ": cannot create the staging directory " + d.writing_ + " (" + errno_text(errno) + ")");
    } else {
        // Straight into the directory: the manifest names each file as it is written, so that
        // even a run that is killed leaves files a later --replace knows as its own.
        output_detail::replace_file(dir + "/" + manifest_name, manifest_text(d.command_, {}));
    }
    d.claimed_ = true;
    return d;
}

OutputDir& OutputDir::operator=(OutputDir&& other) noexcept {
    if (this != &other) {
        release();
        dir_ = std::move(other.dir_);
        writing_ = std::move(other.writing_);
        command_ = std::move(other.command_);
        policy_ = std::move(other.policy_);
        earlier_ = std::move(other.earlier_);
        staging_ = other.staging_;
        committed_ = other.committed_;
        claimed_ = other.claimed_;
        lock_ = std::move(other.lock_);
    }
    return *this;
}

void OutputDir::record(const std::string& name) const {
    if (staging_) return;  // the staging directory's listing is the manifest at commit
    const std::string path = dir_ + "/" + manifest_name;
    const int fd = open(path.c_str(), O_WRONLY | O_APPEND | O_CLOEXEC | O_NOFOLLOW);
    if (fd < 0) return;
    const std::string line = name + "\n";
    (void)!::write(fd, line.data(), line.size());
    close(fd);
}

void OutputDir::write(const std::string& name, const std::string& content) const {
    if (!lock_.held()) throw std::logic_error("OutputDir::write on a directory that was not claimed");
    if (name.empty() || name.find('/') != std::string::npos || name == "." || name == ".." || bookkeeping(name))
        throw std::logic_error("OutputDir::write: '" + name + "' is not a plain file name of an output");
    if (!policy_.fixed_files.empty() && std::find(policy_.fixed_files.begin(), policy_.fixed_files.end(), name) == policy_.fixed_files.end())
        throw std::logic_error("OutputDir::write: '" + name + "' is not one of the files this command declared");
    const std::string path = writing_ + "/" + name;
    output_detail::check_target(path, policy_.option, policy_.inputs, false);
    struct stat st{};
    const bool is_new = lstat(path.c_str(), &st) != 0;
    output_detail::replace_file(path, content);
    if (is_new) record(name);
}

void OutputDir::commit() {
    if (!lock_.held() || committed_) return;
    const std::vector<std::string> mine = entries(writing_);
    if (staging_) {
        for (const auto& name : earlier_)
            if (unlink((dir_ + "/" + name).c_str()) != 0 && errno != ENOENT)
                throw std::runtime_error("cannot remove " + dir_ + "/" + name + " of the earlier run: " + errno_text(errno) + "; this run's files are in " +
                                         writing_);
        for (const auto& name : mine)
            if (rename((writing_ + "/" + name).c_str(), (dir_ + "/" + name).c_str()) != 0)
                throw std::runtime_error("cannot move " + name + " into " + dir_ + ": " + errno_text(errno) + "; this run's files are in " + writing_);
    }
    output_detail::replace_file(dir_ + "/" + manifest_name, manifest_text(command_, mine));
    if (staging_) rmdir(writing_.c_str());
    committed_ = true;
}

void OutputDir::release() noexcept {
    if (!lock_.held()) return;
    if (claimed_ && !committed_) {
        if (staging_) {
            remove_tree(writing_);  // the earlier run's files stay as they were
        } else {
            try {  // what was written is this run's: listed, so that --replace may take it later
                output_detail::replace_file(dir_ + "/" + manifest_name, manifest_text(command_, entries(dir_)));
            } catch (...) {
            }
        }
    }
    lock_.release();
}

}  // namespace suite
