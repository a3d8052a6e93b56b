#pragma once
// A RAPL energy counter for end-to-end tests: `energy_uj` reads as a regular file, as in sysfs
// (the suite refuses anything else, a FIFO included), and a thread of the test moves it by
// `step_uj` about every `period`. The counter moves with time, not with the reads: a repetition
// measures a whole multiple of `step_uj`, as many steps as fell inside it.
//
// Each value is a new small file and `energy_uj` a symlink swapped to it in one rename, so a
// reader never sees half a number. (Renaming a new regular file over the old one would do the
// same, but ext4 flushes the new file's data on such a rename, about a millisecond a step.)
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <system_error>
#include <thread>

namespace suite::test {

class MovingEnergyCounter {
public:
    MovingEnergyCounter(const std::string& path, std::uint64_t first_uj, std::uint64_t step_uj,
                        std::chrono::microseconds period = std::chrono::microseconds(50))
        : path_(path), value_(first_uj), step_(step_uj), period_(period) {
        std::filesystem::remove(path_);
        write(value_);
        thread_ = std::thread([this] { serve(); });
    }
    ~MovingEnergyCounter() { stop(); }
    MovingEnergyCounter(const MovingEnergyCounter&) = delete;
    MovingEnergyCounter& operator=(const MovingEnergyCounter&) = delete;

    // From now on the file is gone: a reader gets ENOENT, as when a sysfs file disappears.
    void remove() {
        stop();
        std::filesystem::remove(path_);
    }
    void stop() {
        done_ = true;
        if (thread_.joinable()) thread_.join();
    }
    std::uint64_t steps() const { return steps_; }

private:
    // The value's own file beside energy_uj, then the link to it, swapped in.
    void write(std::uint64_t uj) {
        const std::string name =
            std::filesystem::path(path_).filename().string() + ".value" + std::to_string(written_ % 64);
        const std::string file = std::filesystem::path(path_).parent_path() / name;
        std::filesystem::remove(file);  // 64 steps old: no reader still has it open
        std::ofstream(file) << uj << "\n";
        const std::string link = path_ + ".link";
        std::filesystem::remove(link);
        std::filesystem::create_symlink(name, link);
        std::filesystem::rename(link, path_);
        ++written_;
    }
    void serve() {
        while (!done_) {
            std::this_thread::sleep_for(period_);
            value_ += step_;
            write(value_);
            steps_ += 1;
        }
    }

    std::string path_;
    std::uint64_t value_, step_;
    std::chrono::microseconds period_;
    std::uint64_t written_ = 0;
    std::atomic<bool> done_{false};
    std::atomic<std::uint64_t> steps_{0};
    std::thread thread_;
};

}  // namespace suite::test
