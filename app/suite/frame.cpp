#include "app/suite/frame.hpp"

#include <iostream>
#include <stdexcept>
#include <utility>

namespace suite {

namespace {

// A signal handler can reach no object, only a flag: one for the one frame alive.
std::atomic<int> frame_stop{0};
std::atomic<bool> frame_alive{false};

extern "C" void frame_on_signal(int sig) { frame_stop.store(sig); }

}  // namespace

CommandFrame::CommandFrame(std::string program, SecondSignal second) : program_(std::move(program)) {
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
    file_.release();
    dir_.release();
    frame_alive.store(false);
}

const std::atomic<int>* CommandFrame::stop_flag() const { return &frame_stop; }

const OutputFile& CommandFrame::claim_file(const std::string& path, const std::string& option, const std::vector<FileIdentity>& inputs) {
    if (file_.claimed() || !dir_.path().empty()) throw std::logic_error("CommandFrame: the output is claimed already");
    file_ = OutputFile::claim(path, option, inputs);
    return file_;
}

const OutputDir& CommandFrame::claim_dir(const std::string& dir, const std::string& option, const std::vector<FileIdentity>& inputs) {
    if (file_.claimed() || !dir_.path().empty()) throw std::logic_error("CommandFrame: the output is claimed already");
    dir_ = OutputDir::claim(dir, option, inputs);
    return dir_;
}

int CommandFrame::finish(int status, const std::string& done) const {
    const int sig = signal();
    if (sig == 0) return status;
    std::cerr << program_ << ": interrupted by signal " << sig << " after " << done << "\n";
    return 128 + sig;
}

}  // namespace suite
