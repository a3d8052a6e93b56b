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

#include <functional>
#include <set>
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
    const std::string& path() const { return path_; }
    int fd() const { return fd_; }
    void release() noexcept;

private:
    std::string path_;
    int fd_ = -1;
};

class OutputFile {
public:
    // `option` names where the path came from in messages, e.g. "--out" or "--markdown".
    static OutputFile claim(const std::string& path, const std::string& option,
                            const std::vector<FileIdentity>& inputs = {});

    // Replaces the file's content atomically (temporary file, fsync, rename, directory fsync).
    void write(const std::string& content) const;
    // The same, for a document that says whether it is complete. An incomplete one (an
    // interrupted run's) never replaces a file that held a complete result when it was claimed:
    // it goes to incomplete_path() instead, and a complete write removes an incomplete document
    // there (this run's, or an earlier interrupted run's).
    // Returns the path written.
    std::string write(const std::string& content, bool complete) const;
    // Whether the file held a complete result (`"complete": true`) when it was claimed.
    bool earlier_complete() const { return earlier_complete_; }
    const std::string& path() const { return path_; }
    bool claimed() const { return lock_.held(); }
    const std::string& lock_path() const { return lock_.path(); }
    int lock_fd() const { return lock_.fd(); }
    // Removes the lock file and drops the lock (the destructor does it too).
    void release() noexcept { lock_.release(); }

private:
    std::string path_, option_;
    std::vector<FileIdentity> inputs_;
    OutputLock lock_;
    bool earlier_complete_ = false;
    mutable bool wrote_incomplete_ = false;
};

// Where an incomplete document goes instead of a complete one at `path`: r.json -> r.incomplete.json.
std::string incomplete_path(const std::string& path);

// What a directory of outputs may hold when it is claimed, and who claims it.
struct DirPolicy {
    std::string option = "--out";        // named in messages
    std::string command{};               // e.g. "suite mpm": recorded with the files, named in refusals
    std::vector<FileIdentity> inputs{};  // files of the run that must not be written
    bool replace_earlier = false;        // an earlier run's files are replaced (--replace), not refused
    // A command that always writes the same few files (history html: index.html, chart.min.js)
    // names them: they are replaced one by one, the directory's other files are left alone
    // (a page's folder may hold a CNAME), and no manifest is kept: no stale file can build up.
    std::vector<std::string> fixed_files{};
};

// A directory of outputs: one run's files (unless the policy names a fixed set of files).
// Created if missing (its parent must exist), locked as a whole, never a symlink. It may hold only the files of one
// earlier suite run, as its manifest `.suite-files` lists them (the command on the first line, a name a line), and
// those only when the policy replaces them: any other file in it (the user's, a FIFO where an
// output goes, an input) is refused when the directory is claimed, before any work. An earlier
// run's files are replaced at commit(): until then this run writes into a staging directory
// inside it, so that a failure (an exception, release() without commit()) leaves the earlier
// set as it was, and a commit leaves this run's set alone. Every file is written through the
// same policy as an OutputFile.
class OutputDir {
public:
    static OutputDir claim(const std::string& dir, const DirPolicy& policy);
    static OutputDir claim(const std::string& dir, const std::string& option,
                           const std::vector<FileIdentity>& inputs = {}) {
        return claim(dir, DirPolicy{.option = option, .inputs = inputs});
    }
    // The checks of claim() alone, creating and locking nothing (for --dry-run).
    static void check(const std::string& dir, const DirPolicy& policy);
    static void check(const std::string& dir, const std::string& option) { check(dir, DirPolicy{.option = option}); }

    OutputDir() = default;
    OutputDir(OutputDir&&) noexcept = default;
    OutputDir& operator=(OutputDir&& other) noexcept;
    OutputDir(const OutputDir&) = delete;
    OutputDir& operator=(const OutputDir&) = delete;
    ~OutputDir() { release(); }

    // Writes `name` (a plain file name, no '/') atomically, under the same policy.
    void write(const std::string& name, const std::string& content);
    // Runs `writer` on writing_path() (a program that writes files of its own there, such as a
    // plot script); the files it made are this run's. Returns what the writer returns.
    std::string with_writer(const std::function<std::string(const std::string& dir)>& writer);
    const std::string& path() const { return dir_; }
    const std::string& lock_path() const { return lock_.path(); }
    int lock_fd() const { return lock_.fd(); }
    // Where this run's files go until commit(): the directory, or its staging directory while
    // an earlier run's files are being replaced. For programs that write files of their own there.
    const std::string& writing_path() const { return writing_; }
    // The run is over (finished, or stopped at a safe point): its files become the directory's,
    // the earlier run's removed, the manifest rewritten. Throws std::runtime_error when a file
    // cannot be moved or removed; the staging directory then keeps what was not moved, and the
    // manifest lists every file the directory may hold, so that a later --replace takes them.
    void commit();
    // An interrupted replacement: this run's files, incomplete, are kept in DIR/.suite-incomplete
    // (an older one removed) and the earlier complete set stays as it was. Returns that path,
    // or "" when this claim replaces nothing (its files are in the directory already).
    std::string keep_incomplete();
    // Whether this claim replaces an earlier run's files (they stay until commit()).
    bool replacing() const { return staging_ && !committed_; }
    // Drops the claim. Without commit(), a replacement is abandoned (the staging directory
    // removed, the earlier files untouched); files written straight into the directory stay,
    // listed in its manifest.
    void release() noexcept;

private:
    void record(const std::string& name);
    std::string dir_, writing_;
    DirPolicy policy_;
    std::vector<std::string> earlier_;  // the earlier run's files, removed at commit
    std::set<std::string> written_;     // this run's files: write() and with_writer()'s
    bool staging_ = false, committed_ = false;
    bool claimed_ = false;  // claim() finished: what is in the directory is this run's
    OutputLock lock_;
};

// The policy check alone, without a lock or a write: throws UsageError if `path` may not be
// written (for --dry-run, which writes nothing but must refuse what the real run would).
void check_output_target(const std::string& path, const std::string& option,
                         const std::vector<FileIdentity>& inputs = {});

}  // namespace suite
