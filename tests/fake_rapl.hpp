#pragma once
// A RAPL energy counter for end-to-end tests that does not depend on timing: `energy_uj` is
// replaced by a named pipe, and every read of it by the suite gets the next value, `step_uj`
// more than the last. So each repetition (one read at its start, one at its stop) measures
// exactly `step_uj`, however loaded the machine is. (reads() counts values handed out, one ahead.)
#include <fcntl.h>
#include <sys/ioctl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <string>
#include <system_error>
#include <thread>

namespace suite::test {

class FifoEnergyCounter {
public:
    FifoEnergyCounter(const std::string& path, std::uint64_t first_uj, std::uint64_t step_uj) : path_(path), value_(first_uj), step_(step_uj) {
        std::filesystem::remove(path_);
        if (mkfifo(path_.c_str(), 0644) != 0) throw std::system_error(errno, std::generic_category(), "mkfifo " + path_);
        thread_ = std::thread([this] { serve(); });
    }
    ~FifoEnergyCounter() { stop(); }
    FifoEnergyCounter(const FifoEnergyCounter&) = delete;
    FifoEnergyCounter& operator=(const FifoEnergyCounter&) = delete;

    // From now on the file is gone: a reader gets ENOENT, as when a sysfs file disappears.
    void remove() {
        stop();
        std::filesystem::remove(path_);
    }
    void stop() {
        done_ = true;
        if (thread_.joinable()) thread_.join();
    }
    std::uint64_t reads() const { return reads_; }

private:
    // The pipe always holds exactly one value: the next is written once the last was read. The
    // test holds the pipe open for reading and writing, so readers never block in open() and a
    // value written after one reader closed waits for the next.
    void serve() {
        const int fd = open(path_.c_str(), O_RDWR | O_CLOEXEC);
        if (fd < 0) return;
        while (!done_) {
            int queued = 0;
            if (ioctl(fd, FIONREAD, &queued) == 0 && queued == 0) {
                const std::string text = std::to_string(value_) + "\n";  // one write below PIPE_BUF: read whole
                if (write(fd, text.data(), text.size()) == static_cast<ssize_t>(text.size())) {
                    value_ += step_;
                    reads_ += 1;
                }
            }
            std::this_thread::sleep_for(std::chrono::microseconds(20));
        }
        close(fd);
    }

    std::string path_;
    std::uint64_t value_, step_;
    std::atomic<bool> done_{false};
    std::atomic<std::uint64_t> reads_{0};
    std::thread thread_;
};

}  // namespace suite::test
