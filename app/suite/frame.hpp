#pragma once
// One frame around every command that runs long and writes what it finds (run, mpm, matrix,
// traverse, and suite-mpi's ranks), so that each keeps the same promise:
//
//  - its output, a file or a directory, is checked and locked before the work starts, and the
//    lock file is removed when the frame ends, however the command ended; a directory holds
//    one run's files, replaced as a set when the command finishes (OutputDir);
//  - SIGINT and SIGTERM do not kill it: they ask it to stop at its next safe point (between
//    points, steps or orderings, where everything finished is consistent). The command then
//    writes what it finished, marked "complete": false, and finish() says on stderr what was
//    interrupted and returns 128+N. A second signal ends the process at once (unless the frame
//    was made to wait, as suite-mpi's ranks are: theirs removes the lock file at the first
//    signal, since mpirun follows its SIGTERM with a SIGKILL); the files on disk stay valid
//    either way, since every write replaces its file atomically.
//
// A command builds the frame once its options are checked, claims its output through it, and
// asks stop_requested() at its safe points (or hands stop_flag() to the engine: the runner and
// the MPM time loop take one). One frame at a time; it restores the previous handlers when it ends.
#include <signal.h>

#include <atomic>
#include <string>
#include <vector>

#include "harness/common/output_file.hpp"

namespace suite {

class CommandFrame {
public:
    enum class SecondSignal { ends_process, waits };
    // `program` names the program in its messages ("suite", "suite-mpi").
    explicit CommandFrame(std::string program = "suite", SecondSignal second = SecondSignal::ends_process);
    ~CommandFrame();
    CommandFrame(const CommandFrame&) = delete;
    CommandFrame& operator=(const CommandFrame&) = delete;

    // The output, checked and locked now (OutputFile::claim, OutputDir::claim: UsageError when
    // the policy refuses it). The frame keeps the claim until it ends.
    const OutputFile& claim_file(const std::string& path, const std::string& option, const std::vector<FileIdentity>& inputs = {});
    const OutputDir& claim_dir(const std::string& dir, const DirPolicy& policy);
    const OutputFile* file() const { return file_.claimed() ? &file_ : nullptr; }

    // The signal that asked the command to stop, or 0.
    int signal() const { return stop_flag()->load(); }
    bool stop_requested() const { return signal() != 0; }
    const std::atomic<int>* stop_flag() const;

    // The command is over, its files written: a directory's files become its own (OutputDir::
    // commit). Returns the exit status: `status` when no signal came; otherwise "PROGRAM:
    // interrupted by signal N after DONE" on stderr and 128+N (DONE: what was finished, e.g.
    // "3 of 7 ordering(s)"). A frame that ends without it (an exception) abandons a replacement.
    int finish(int status, const std::string& done);

private:
    std::string program_;
    SecondSignal second_;
    OutputFile file_;
    OutputDir dir_;
    struct sigaction old_int_ {}, old_term_ {};
};

}  // namespace suite
