#pragma once
// One frame around every command that runs long and writes what it finds (run, mpm, matrix,
// traverse, and suite-mpi's ranks), so that each keeps the same promise:
//
//  - its output, a file or a directory, is checked and locked before the work starts, and the
//    lock file is removed when the frame ends, however the command ended short of being
//    killed; a directory holds one run's files, replaced as a set when the command finishes
//    (OutputDir);
//  - SIGINT and SIGTERM do not kill it: they ask it to stop at its next safe point (between
//    points, steps or orderings, where everything finished is consistent). The command then
//    writes what it finished, marked "complete": false, and finish() says on stderr what was
//    interrupted and returns 128+N. A second signal ends the process at once (unless the frame
//    waits for ranks, as suite-mpi's do); the files on disk stay valid either way, since every
//    write replaces its file atomically. A signal the process was started with ignored stays
//    ignored.
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
    // ends_process: a second SIGINT or SIGTERM ends the process at once.
    // waits_for_ranks (suite-mpi): signals only ask for the stop, so that no rank is left alone
    // in a collective; and the first one removes the output's lock file, since mpirun follows
    // its SIGTERM with a SIGKILL that a rank blocked in a collective does not outlive.
    enum class SecondSignal { ends_process, waits_for_ranks };
    // `program` names the program in its messages ("suite", "suite-mpi").
    explicit CommandFrame(std::string program = "suite", SecondSignal second = SecondSignal::ends_process);
    ~CommandFrame();
    CommandFrame(const CommandFrame&) = delete;
    CommandFrame& operator=(const CommandFrame&) = delete;

    // The output, checked and locked now (OutputFile::claim, OutputDir::claim: UsageError when
    // the policy refuses it). The frame keeps the claim until it ends.
    const OutputFile& claim_file(const std::string& path, const std::string& option,
                                 const std::vector<FileIdentity>& inputs = {});
    OutputDir& claim_dir(const std::string& dir, const DirPolicy& policy);
    const OutputFile* file() const { return file_.claimed() ? &file_ : nullptr; }

    // The signal that asked the command to stop (the first), or 0.
    int stop_signal() const { return stop_flag()->load(); }
    bool stop_requested() const { return stop_signal() != 0; }
    const std::atomic<int>* stop_flag() const;

    // The command is over, its files written: a directory's files become its own (OutputDir::
    // commit), unless `status` says the run failed (1, 3) and they would replace an earlier
    // run's, which are then kept. Returns the exit status: `status` when no signal came or the
    // work was `complete` before it came; otherwise "PROGRAM: interrupted by signal N after
    // DONE" on stderr and 128+N (DONE: what was finished, e.g. "3 of 7 ordering(s)"). A frame
    // that ends without finish() (an exception) abandons a replacement.
    int finish(int status, const std::string& done, bool complete);

private:
    std::string program_;
    SecondSignal second_;
    OutputFile file_;
    OutputDir dir_;
    struct sigaction old_int_ {
    }, old_term_{};
};

}  // namespace suite
