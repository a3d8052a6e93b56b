#include "app/suite/frame.hpp"

#include <unistd.h>

#include <algorithm>
#include <iostream>
#include <stdexcept>
#include <utility>

namespace suite {

namespace {

// A signal handler can reach no object, only a flag: one for the one frame alive.
std::atomic<int> frame_stop{0};
std::atomic<bool> frame_alive{false};
// A frame that waits for the other ranks (suite-mpi) removes its lock file at the first
// signal: when a rank dies, mpirun sends the others SIGTERM and then SIGKILL, and a rank
// blocked in a collective never reaches its safe point. unlink is async-signal-safe; the file
// on disk is valid whatever happens next (every write is atomic).
char frame_lock[4096] = {};
std::atomic<bool> frame_unlinks{false};

extern "C" void frame_on_signal(int sig) {
    frame_stop.store(sig);
    if (frame_unlinks.load() && frame_lock[0]) unlink(frame_lock);
}

// Arms the handler's unlink for the claimed output's lock file.
void remember_lock(const std::string& path, bool unlink_on_signal) {
    frame_unlinks.store(false);
    if (!unlink_on_signal || path.size() >= sizeof frame_lock) return;
    std::copy(path.begin(), path.end(), frame_lock);
    frame_lock[path.size()] = '\0';
    frame_unlinks.store(true);
}

}  // namespace

CommandFrame::CommandFrame(std::string program, SecondSignal second) : program_(std::move(program)), second_(second) {
    if (frame_alive.exchange(true)) throw std::logic_error("a second CommandFrame while one is alive: a command has one frame");
    frame_stop.store(0);
    struct sigaction sa {};
    sa.sa_handler = frame_on_signal;
    sa.sa_flags = second == SecondSignal::ends_process ? SA_RESETHAND : 0;
    sigemptyset(&sa.sa_mask);
    sigaction(SIGINT, &sa, &old_int_);
    sigaction(SIGTERM, &sa, &old_term_);
}

CommandFrame::~CommandFrame() {
    sigaction(SIGINT, &old_int_, nullptr);
    sigaction(SIGTERM, &old_term_, nullptr);
    frame_unlinks.store(false);
    file_.release();
    dir_.release();
    frame_alive.store(false);
}

const std::atomic<int>* CommandFrame::stop_flag() const { return &frame_stop; }

const OutputFile& CommandFrame::claim_file(const std::string& path, const std::string& option, const std::vector<FileIdentity>& inputs) {
    if (file_.claimed() || !dir_.path().empty()) throw std::logic_error("CommandFrame: the output is claimed already");
    file_ = OutputFile::claim(path, option, inputs);
    remember_lock(file_.lock_path(), second_ == SecondSignal::waits);
    return file_;
}

const OutputDir& CommandFrame::claim_dir(const std::string& dir, const DirPolicy& policy) {
    if (file_.claimed() || !dir_.path().empty()) throw std::logic_error("CommandFrame: the output is claimed already");
    dir_ = OutputDir::claim(dir, policy);
    remember_lock(dir_.lock_path(), second_ == SecondSignal::waits);
    return dir_;
}

int CommandFrame::finish(int status, const std::string& done) {
    dir_.commit();
    const int sig = signal();
    if (sig == 0) return status;
    std::cerr << program_ << ": interrupted by signal " << sig << " after " << done << "\n";
    return 128 + sig;
}

}  // namespace suite
