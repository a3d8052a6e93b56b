#include "harness/common/output_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "harness/common/input_file.hpp"
#include "harness/common/output_detail.hpp"
#include "harness/common/sysfs_file.hpp"  // file_kind
#include "harness/common/units.hpp"

namespace suite {

namespace output_detail {

std::string errno_text(int err) { return std::strerror(err); }

std::string parent_of(const std::string& path) {
    const auto end = path.find_last_not_of('/');
    if (end == std::string::npos) return "/";
    const auto slash = path.rfind('/', end);
    if (slash == std::string::npos) return ".";
    return slash == 0 ? "/" : path.substr(0, slash);
}

const FileIdentity* same_as_input(const struct stat& st, const std::vector<FileIdentity>& inputs) {
    for (const auto& in : inputs)
        if (in.dev == st.st_dev && in.ino == st.st_ino) return &in;
    return nullptr;
}

// The checks every target passes, at claim time and again before each rename (the path may
// have changed in between). `usage` selects the exception: UsageError when claiming,
// runtime_error when writing.
void check_target(const std::string& path, const std::string& option, const std::vector<FileIdentity>& inputs,
                  bool usage) {
    auto refuse = [&](const std::string& why) -> void {
        const std::string msg = option + "=" + path + why;
        if (usage) throw UsageError(msg);
        throw std::runtime_error("cannot write " + msg + " (the previous file, if any, is unchanged)");
    };
    if (path.empty()) refuse(" is empty; give a file name, e.g. " + option + "=results/run.json");
    if (path.back() == '/') refuse(" ends in '/'; give a file name, e.g. " + option + "=" + path + "run.json");
    struct stat st {};
    if (lstat(path.c_str(), &st) == 0) {
        if (S_ISDIR(st.st_mode)) refuse(" is a directory; give a file name, e.g. " + option + "=" + path + "/run.json");
        if (!S_ISREG(st.st_mode))
            refuse(std::string(" exists and is ") + file_kind(st.st_mode) +
                   ", not a regular file; the suite writes only to a regular file or a new name");
        if (const FileIdentity* in = same_as_input(st, inputs))
            refuse(" is the same file as the input " + in->path + "; writing it would destroy that input");
        if (faccessat(AT_FDCWD, path.c_str(), W_OK, AT_EACCESS) != 0)
            refuse(" exists and this user may not write it (" + errno_text(errno) + "); it is left as it is");
    } else if (errno != ENOENT) {
        refuse(" cannot be examined: " + errno_text(errno));
    }
    const std::string dir = parent_of(path);
    if (stat(dir.c_str(), &st) != 0 || !S_ISDIR(st.st_mode)) refuse(": the directory '" + dir + "' does not exist");
    if (!usage) return;
    // A file is written through a temporary file beside it: the directory must take a new
    // file. Create and remove one to know (access(W_OK) says yes to root even on /proc).
    const std::string probe = path + ".probe." + std::to_string(getpid());
    const int fd = open(probe.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0600);
    if (fd < 0) refuse(": the directory '" + dir + "' is not writable (" + errno_text(errno) + ")");
    close(fd);
    unlink(probe.c_str());
}

// Writes `content` to a new temporary file beside `path`, fsyncs it and renames it over
// `path`; on any failure removes the temporary file and throws.
void replace_file(const std::string& path, const std::string& content) {
    const std::string tmp = path + ".tmp." + std::to_string(getpid());
    auto fail = [&](const std::string& what, int err) {
        unlink(tmp.c_str());
        throw std::runtime_error("cannot write " + path + ": " + what + ": " + errno_text(err) +
                                 " (the previous file, if any, is unchanged)");
    };
    unlink(tmp.c_str());  // a leftover of an earlier process with this pid, never anyone's data
    // Keep the permissions of the file being replaced (a 0600 result stays 0600).
    mode_t mode = 0644;
    struct stat old {};
    if (stat(path.c_str(), &old) == 0) mode = old.st_mode & 07777;
    const int fd = open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0600);
    if (fd < 0) fail("cannot create " + tmp, errno);
    const char* p = content.data();
    std::size_t left = content.size();
    while (left > 0) {
        const ssize_t n = ::write(fd, p, left);
        if (n < 0) {
            if (errno == EINTR) continue;
            const int err = errno;
            close(fd);
            fail("write failed", err);
        }
        p += n;
        left -= static_cast<std::size_t>(n);
    }
    if (fchmod(fd, mode) != 0) {
        const int err = errno;
        close(fd);
        fail("cannot set its mode", err);
    }
    if (fsync(fd) != 0) {
        const int err = errno;
        close(fd);
        fail("fsync failed", err);
    }
    if (close(fd) != 0) fail("close failed", errno);
    if (rename(tmp.c_str(), path.c_str()) != 0) fail("rename failed", errno);
    // The rename itself reaches the disk only when the directory is synced.
    if (const int dfd = open(parent_of(path).c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC); dfd >= 0) {
        fsync(dfd);
        close(dfd);
    }
}

}  // namespace output_detail

namespace {

using namespace output_detail;

// The pid a lock file names (its holder writes it there after locking), or "" if none.
std::string pid_in(int fd) {
    char buf[32] = {};
    const ssize_t n = pread(fd, buf, sizeof buf - 1, 0);
    std::string s = n > 0 ? std::string(buf, static_cast<std::size_t>(n)) : "";
    while (!s.empty() && (s.back() == '\n' || s.back() == ' ')) s.pop_back();
    for (char c : s)
        if (c < '0' || c > '9') return "";
    return s;
}

}  // namespace

namespace output_detail {

// Opens and locks `lock_path` (a regular file, created if missing) for `what`; returns the fd.
// Refuses, naming the holder, when another process (or another claim in this one) holds it.
// Open-file-description locks: unlike POSIX record locks they belong to this open, so a
// second claim of the same file in this process conflicts too, and closing another
// descriptor of the file does not drop them.
int take_lock(const std::string& lock_path, const std::string& what) {
    for (int attempt = 0; attempt < 8; ++attempt) {
        const int fd = open(lock_path.c_str(), O_RDWR | O_CREAT | O_NOFOLLOW | O_CLOEXEC | O_NONBLOCK, 0644);
        if (fd < 0) {
            const int err = errno;
            if (err == ELOOP) throw UsageError(what + ": its lock file " + lock_path + " is a symlink; remove it");
            throw UsageError(what + ": cannot create its lock file " + lock_path + " (" + errno_text(err) +
                             "); the directory must be writable by this user");
        }
        struct stat st {};
        if (fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
            close(fd);
            throw UsageError(what + ": its lock file " + lock_path + " is not a regular file; remove it");
        }
        struct flock fl {};
        fl.l_type = F_WRLCK;
        fl.l_whence = SEEK_SET;
        if (fcntl(fd, F_OFD_SETLK, &fl) != 0) {
            const int err = errno;
            const std::string pid = pid_in(fd);
            close(fd);
            if (err == EACCES || err == EAGAIN) {
                if (pid == std::to_string(getpid()))
                    throw UsageError(what + " is named twice as an output of this run; give each output its own file");
                throw UsageError(what + " is being written by another suite run" +
                                 (pid.empty() ? "" : " (pid " + pid + ")") +
                                 "; wait for it to finish or choose another name");
            }
            throw UsageError(what + ": cannot lock " + lock_path + " (" + errno_text(err) + ")");
        }
        // The holder before us removes the lock file when it is done: if the name now points at
        // another file (or none), our lock is on an orphan and protects nothing. Try again.
        struct stat now {};
        if (stat(lock_path.c_str(), &now) != 0 || now.st_dev != st.st_dev || now.st_ino != st.st_ino) {
            close(fd);
            continue;
        }
        // Who holds it, for the message of a run that finds it taken.
        const std::string pid = std::to_string(getpid()) + "\n";
        if (ftruncate(fd, 0) == 0) (void)!pwrite(fd, pid.data(), pid.size(), 0);
        return fd;
    }
    throw UsageError(what + ": its lock file " + lock_path + " keeps changing; another run is starting on it");
}

}  // namespace output_detail

using namespace output_detail;

OutputLock& OutputLock::operator=(OutputLock&& other) noexcept {
    if (this != &other) {
        release();
        path_ = std::move(other.path_);
        fd_ = std::exchange(other.fd_, -1);
    }
    return *this;
}

void OutputLock::release() noexcept {
    if (fd_ < 0) return;
    // Unlink while still holding the lock, so that no one locks the name we are removing; and
    // only our own file: if the name was removed already (a signal handler may do that) and
    // another run has made and locked a new one there, it is that run's.
    struct stat mine {
    }, now{};
    if (fstat(fd_, &mine) == 0 && stat(path_.c_str(), &now) == 0 && mine.st_dev == now.st_dev &&
        mine.st_ino == now.st_ino)
        unlink(path_.c_str());
    close(fd_);
    fd_ = -1;
}

std::vector<FileIdentity> identify_inputs(const std::vector<std::string>& paths) {
    std::vector<FileIdentity> out;
    for (const auto& p : paths) {
        struct stat st {};
        if (!p.empty() && stat(p.c_str(), &st) == 0) out.push_back({st.st_dev, st.st_ino, p});
    }
    return out;
}

void check_output_target(const std::string& path, const std::string& option, const std::vector<FileIdentity>& inputs) {
    check_target(path, option, inputs, true);
}

namespace {

// Whether `path` holds a document that says `"complete": true` (a run's result, a roofline file):
// an incomplete one must not replace it.
bool holds_complete_result(const std::string& path) {
    const InputText in = read_regular_file(path, 256ULL << 20);
    if (!in.ok) return false;
    const nlohmann::json doc = nlohmann::json::parse(in.text, nullptr, false);
    return doc.is_object() && doc.contains("complete") && doc["complete"] == true;
}

}  // namespace

std::string incomplete_path(const std::string& path) {
    const auto dot = path.rfind('.');
    const auto slash = path.rfind('/');
    const bool ext = dot != std::string::npos && (slash == std::string::npos || dot > slash + 1);
    return ext ? path.substr(0, dot) + ".incomplete" + path.substr(dot) : path + ".incomplete";
}

OutputFile OutputFile::claim(const std::string& path, const std::string& option,
                             const std::vector<FileIdentity>& inputs) {
    check_target(path, option, inputs, true);
    OutputFile f;
    f.path_ = path;
    f.option_ = option;
    f.inputs_ = inputs;
    f.lock_ = OutputLock(path + ".lock", take_lock(path + ".lock", option + "=" + path));
    f.earlier_complete_ = holds_complete_result(path);
    // Where an interrupted run's records would go: refused now, like the target, if it cannot be.
    if (f.earlier_complete_) check_target(incomplete_path(path), option, inputs, true);
    return f;
}

void OutputFile::write(const std::string& content) const { write(content, true); }

std::string OutputFile::write(const std::string& content, bool complete) const {
    if (!lock_.held()) throw std::logic_error("OutputFile::write on a file that was not claimed");
    if (!complete && earlier_complete_) {
        const std::string side = incomplete_path(path_);
        check_target(side, option_, inputs_, false);
        replace_file(side, content);
        wrote_incomplete_ = true;
        return side;
    }
    check_target(path_, option_, inputs_, false);
    replace_file(path_, content);
    // Complete now: an incomplete document beside it (this run's interim records, or an earlier
    // interrupted run's) is superseded. Only a regular file that says so is removed.
    if (complete) {
        const std::string side = incomplete_path(path_);
        struct stat st {};
        if (lstat(side.c_str(), &st) == 0 && S_ISREG(st.st_mode)) {
            const InputText in = read_regular_file(side, 256ULL << 20);
            const nlohmann::json doc = in.ok ? nlohmann::json::parse(in.text, nullptr, false) : nlohmann::json();
            if (doc.is_object() && doc.contains("complete") && doc["complete"] == false) unlink(side.c_str());
        }
        wrote_incomplete_ = false;
    }
    return path_;
}

}  // namespace suite
