#include "app/suite/frame.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <iostream>
#include <stdexcept>
#include <utility>

namespace suite {

namespace {

// A signal handler can reach no object, only flags: these are the one frame alive's. The
// handler makes only async-signal-safe calls (atomic stores, sigaction, fstat, stat, unlink)
// and leaves errno as it found it.
std::atomic<int> frame_stop{0};
std::atomic<bool> frame_alive{false};
std::atomic<bool> frame_second_ends{false};  // SecondSignal::ends_process
// SecondSignal::waits_for_ranks removes the output's lock file at the first signal: when a rank
// dies, mpirun sends the others SIGTERM and then SIGKILL, and a rank blocked in a collective
// never reaches its safe point. Once only, and only while the name is still our own lock file
// (another run may have made a new one there since).
char frame_lock[4096] = {};
std::atomic<int> frame_lock_fd{-1};
std::atomic<bool> frame_unlinks{false};

extern "C" void frame_on_signal(int sig) {
    const int saved = errno;
    int none = 0;
    frame_stop.compare_exchange_strong(none, sig);  // the first signal is the one reported
    if (frame_second_ends.load()) {
        // The next SIGINT or SIGTERM, whichever, ends the process at once.
        struct sigaction dfl {};
        dfl.sa_handler = SIG_DFL;
        sigemptyset(&dfl.sa_mask);
        sigaction(SIGINT, &dfl, nullptr);
        sigaction(SIGTERM, &dfl, nullptr);
    }
    if (frame_unlinks.exchange(false)) {
        struct stat mine {
        }, named{};
        const int fd = frame_lock_fd.load();
        if (fd >= 0 && fstat(fd, &mine) == 0 && stat(frame_lock, &named) == 0 && mine.st_dev == named.st_dev &&
            mine.st_ino == named.st_ino)
            unlink(frame_lock);
    }
    errno = saved;
}

// Arms the handler's unlink for the claimed output's lock file (held open as `fd`).
void remember_lock(const std::string& path, int fd, bool unlink_on_signal) {
    frame_unlinks.store(false);
    if (!unlink_on_signal || path.size() >= sizeof frame_lock || fd < 0) return;
    std::copy(path.begin(), path.end(), frame_lock);
    frame_lock[path.size()] = '\0';
    frame_lock_fd.store(fd);
    frame_unlinks.store(true);
}

// Installs the handler for `sig`, unless the process was started with it ignored (a job in
// the background of a non-interactive shell: a Ctrl-C meant for the foreground is not its).
void install(int sig, struct sigaction* old) {
    sigaction(sig, nullptr, old);
    if (old->sa_handler == SIG_IGN) return;
    struct sigaction sa {};
    sa.sa_handler = frame_on_signal;
    sa.sa_flags = SA_RESTART;  // a write the signal interrupts goes on; the flag is read at safe points
    sigemptyset(&sa.sa_mask);
    sigaction(sig, &sa, nullptr);
}

}  // namespace

CommandFrame::CommandFrame(std::string program, SecondSignal second) : program_(std::move(program)), second_(second) {
    if (frame_alive.exchange(true))
        throw std::logic_error("a second CommandFrame while one is alive: a command has one frame");
    frame_stop.store(0);
    frame_second_ends.store(second == SecondSignal::ends_process);
    install(SIGINT, &old_int_);
    install(SIGTERM, &old_term_);
}

CommandFrame::~CommandFrame() {
    sigaction(SIGINT, &old_int_, nullptr);
    sigaction(SIGTERM, &old_term_, nullptr);
    frame_unlinks.store(false);
    frame_lock_fd.store(-1);
    file_.release();
    dir_.release();
    frame_alive.store(false);
}

const std::atomic<int>* CommandFrame::stop_flag() const { return &frame_stop; }

const OutputFile& CommandFrame::claim_file(const std::string& path, const std::string& option,
                                           const std::vector<FileIdentity>& inputs) {
    if (file_.claimed() || !dir_.path().empty()) throw std::logic_error("CommandFrame: the output is claimed already");
    file_ = OutputFile::claim(path, option, inputs);
    remember_lock(file_.lock_path(), file_.lock_fd(), second_ == SecondSignal::waits_for_ranks);
    return file_;
}

OutputDir& CommandFrame::claim_dir(const std::string& dir, const DirPolicy& policy) {
    if (file_.claimed() || !dir_.path().empty()) throw std::logic_error("CommandFrame: the output is claimed already");
    dir_ = OutputDir::claim(dir, policy);
    remember_lock(dir_.lock_path(), dir_.lock_fd(), second_ == SecondSignal::waits_for_ranks);
    return dir_;
}

int CommandFrame::finish(int status, const std::string& done, bool complete) {
    // A run that failed does not replace an earlier run's good files; one that succeeded, or
    // stopped at a safe point with what it finished, does.
    if (status != 0 && status < 128 && dir_.replacing()) {
        std::cerr << program_ << ": note: the earlier run's files in " << dir_.path()
                  << " are kept; this run's are discarded (it failed)\n";
        dir_.release();
    } else if (!complete && stop_signal() != 0 && dir_.replacing()) {
        // An interrupted run never replaces a complete earlier set: what it finished is kept apart.
        const std::string kept = dir_.keep_incomplete();
        std::cerr << program_ << ": note: the earlier run's files in " << dir_.path()
                  << " are kept; this run's, incomplete, are in " << kept << "\n";
    } else {
        dir_.commit();
    }
    const int sig = stop_signal();
    if (sig == 0 || complete) return status;
    std::cerr << program_ << ": interrupted by signal " << sig << " after " << done << "\n";
    return 128 + sig;
}

}  // namespace suite
