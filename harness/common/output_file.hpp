#pragma once
// The one writer of every file the suite writes: result files in every format, --markdown,
// traverse's directory, and whatever later commands write. One policy for all of them:
//
//  - the target is a regular file this user may write, or a new name in a writable directory;
//    never a directory, symlink, device, FIFO or socket, and never a path that is (by device
//    and inode, not by spelling) one of the run's inputs (a mesh, a baseline, a result file read);
//  - an advisory lock (`PATH.lock`, or `DIR/.suite.lock` for a directory) is taken when the
//    target is claimed, before any work: a second run on the same output refuses at start,
//    naming the process that holds it, so no run's records are lost without a word;
//  - each write goes to a temporary file beside the target, is fsynced and renamed over it;
//    on any failure the temporary file is removed and the previous file is left as it was.
//
// Claiming checks the policy and throws UsageError (exit 2) with one line naming the option,
// the path and what is accepted. A write that fails later (disk full, file size limit) throws
// std::runtime_error (exit 1). The lock file is removed when the claim is released.
#include <sys/types.h>

#include <string>
#include <utility>
#include <vector>

namespace suite {

// A file the run reads, identified by device and inode so that another spelling of its path
// (../x.json, a hard link, a symlink to it) is still recognised.
struct FileIdentity {
    dev_t dev = 0;
    ino_t ino = 0;
    std::string path;  // as the user gave it, for messages
};

// The identities of `paths` that exist (a missing input is its reader's error, not ours).
std::vector<FileIdentity> identify_inputs(const std::vector<std::string>& paths);

// The advisory lock on an output's lock file; releasing it removes the lock file.
class OutputLock {
public:
    OutputLock() = default;
    OutputLock(std::string path, int fd) : path_(std::move(path)), fd_(fd) {}
    OutputLock(OutputLock&& other) noexcept : path_(std::move(other.path_)), fd_(std::exchange(other.fd_, -1)) {}
    OutputLock& operator=(OutputLock&& other) noexcept;
    OutputLock(const OutputLock&) = delete;
    OutputLock& operator=(const OutputLock&) = delete;
    ~OutputLock() { release(); }

    bool held() const { return fd_ >= 0; }
    void release() noexcept;

private:
    std::string path_;
    int fd_ = -1;
};

class OutputFile {
public:
    // `option` names where the path came from in messages, e.g. "--out" or "--markdown".
    static OutputFile claim(const std::string& path, const std::string& option, const std::vector<FileIdentity>& inputs = {});

    // Replaces the file's content atomically (temporary file, fsync, rename, directory fsync).
    void write(const std::string& content) const;
    const std::string& path() const { return path_; }
    bool claimed() const { return lock_.held(); }
    // Removes the lock file and drops the lock (the destructor does it too).
    void release() noexcept { lock_.release(); }

private:
    std::string path_, option_;
    std::vector<FileIdentity> inputs_;
    OutputLock lock_;
};

// A directory of outputs: created if missing (its parent must exist), locked as a whole, and
// every file in it written through the same policy as an OutputFile.
class OutputDir {
public:
    static OutputDir claim(const std::string& dir, const std::string& option, const std::vector<FileIdentity>& inputs = {});
    // The checks of claim() alone, creating and locking nothing (for --dry-run).
    static void check(const std::string& dir, const std::string& option);

    // Writes DIR/name (a plain file name, no '/') atomically, under the same policy.
    void write(const std::string& name, const std::string& content) const;
    const std::string& path() const { return dir_; }
    void release() noexcept { lock_.release(); }

private:
    std::string dir_, option_;
    std::vector<FileIdentity> inputs_;
    OutputLock lock_;
};

// The policy check alone, without a lock or a write: throws UsageError if `path` may not be
// written (for --dry-run, which writes nothing but must refuse what the real run would).
void check_output_target(const std::string& path, const std::string& option, const std::vector<FileIdentity>& inputs = {});

}  // namespace suite
