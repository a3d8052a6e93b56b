#pragma once
// Made-up runs for the history's tests, cut from the committed fixture vm-native.json (a real run
// on the development VM): a few of its bandwidth records, each given repetition times drawn from
// a level and a seeded noise, its rates recomputed from them as suite computes them (STREAM bytes
// over the time), and the run stamped with a commit and a date; and a process that holds a
// database locked. Header-only.
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "harness/results/sqlite_db.hpp"
#include "tests/process.hpp"

namespace suite::test {

// A seeded normal draw: Box-Muller on mt19937_64, whose output the standard fixes (the standard
// library's normal_distribution is not the same on every implementation).
class Gauss {
public:
    explicit Gauss(std::uint64_t seed) : rng_(seed) {}
    double operator()() {
        const double u1 = (static_cast<double>(rng_() >> 11) + 0.5) / 9007199254740992.0;
        const double u2 = static_cast<double>(rng_() >> 11) / 9007199254740992.0;
        return std::sqrt(-2 * std::log(u1)) * std::cos(6.283185307179586 * u2);
    }

private:
    std::mt19937_64 rng_;
};

// The first `points` records of vm-native.json (bandwidth points of copy, then triad, then add).
inline nlohmann::json fixture_run(std::size_t points) {
    nlohmann::json doc =
        nlohmann::json::parse(slurp(std::string(SUITE_SOURCE_DIR) + "/tests/fixtures/results/vm-native.json"));
    auto& results = doc["results"];
    results.erase(results.begin() + static_cast<std::ptrdiff_t>(points), results.end());
    return doc;
}

// Gives `record` these repetition times and recomputes its time statistics and rates from them.
inline void set_times(nlohmann::json& record, std::vector<double> times) {
    record["time_s"]["samples"] = times;
    std::vector<double> sorted = times;
    std::sort(sorted.begin(), sorted.end());
    const std::size_t n = sorted.size();
    const double median = n % 2 ? sorted[n / 2] : (sorted[n / 2 - 1] + sorted[n / 2]) / 2;
    double sum = 0;
    for (double t : times) sum += t;
    record["time_s"]["min"] = sorted.front();
    record["time_s"]["max"] = sorted.back();
    record["time_s"]["median"] = median;
    record["time_s"]["mean"] = sum / static_cast<double>(n);
    const auto& work = record["work_per_repetition"];
    for (const auto& [kind, bytes] :
         {std::pair{"stream", "stream_bytes"}, std::pair{"hardware_estimate", "hardware_bytes_estimate"}}) {
        const double b = work[bytes].get<double>();
        record["bandwidth_gbps"][kind]["best"] = b / sorted.front() / 1e9;
        record["bandwidth_gbps"][kind]["median"] = b / median / 1e9;
    }
}

// Repetition times around `level` times the record's own median time: `reps` of them, each with a
// relative noise of `noise` (a standard deviation).
inline std::vector<double> noisy_times(const nlohmann::json& record, double level, double noise, Gauss& g,
                                       std::size_t reps = 5) {
    const double base = record["time_s"]["median"].get<double>() * level;
    std::vector<double> out;
    for (std::size_t i = 0; i < reps; ++i) out.push_back(base * (1 + noise * g()));
    return out;
}

// The commit and date of run i of a made-up history: hourly from 2026-01-01.
inline std::string made_up_commit(std::size_t i) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "c%011llx",
                  static_cast<unsigned long long>((i + 1) * 0x9e3779b1ULL % 0xfffffffffffULL));
    return buf;
}

inline void stamp(nlohmann::json& doc, std::size_t i) {
    char date[64];
    std::snprintf(date, sizeof date, "2026-01-%02zuT%02zu:00:00Z", 1 + i / 24, i % 24);
    doc["context"]["date"] = date;
    doc["context"]["git_revision"] = made_up_commit(i);
}

inline void save_json(const nlohmann::json& doc, const std::string& path) { std::ofstream(path) << doc.dump(1); }

// FNV-1a of a file's bytes: "untouched" is the same hash before and after.
inline std::uint64_t file_hash(const std::string& path) {
    std::uint64_t h = 1469598103934665603ULL;
    for (unsigned char c : slurp(path)) h = (h ^ c) * 1099511628211ULL;
    return h;
}

// Another process that holds an exclusive lock on a database (BEGIN EXCLUSIVE) until this object
// is destroyed. A process of its own: SQLite's locks are POSIX locks, which belong to a process,
// and the test's own reads of the file's bytes would drop them, closing a descriptor of the file.
class LockHolder {
public:
    explicit LockHolder(const std::string& db) {
        int ready[2], release[2];
        if (pipe(ready) != 0 || pipe(release) != 0) throw std::system_error(errno, std::generic_category(), "pipe");
        pid_ = fork();
        if (pid_ < 0) throw std::system_error(errno, std::generic_category(), "fork");
        if (pid_ == 0) {
            close(ready[0]);
            close(release[1]);
            int status = 0;
            try {
                SqlDatabase h = SqlDatabase::open(db, {true, false, 1000});
                h.exec("BEGIN EXCLUSIVE");
                char c = '1';
                if (write(ready[1], &c, 1) != 1 || read(release[0], &c, 1) < 0)
                    status = 1;  // read: 0 at the parent's close
            } catch (...) {
                status = 1;
            }
            _exit(status);
        }
        close(ready[1]);
        close(release[0]);
        char c = 0;
        held_ = read(ready[0], &c, 1) == 1;
        close(ready[0]);
        release_ = release[1];
    }
    ~LockHolder() {
        close(release_);
        waitpid(pid_, nullptr, 0);
    }
    LockHolder(const LockHolder&) = delete;
    LockHolder& operator=(const LockHolder&) = delete;
    bool held() const { return held_; }

private:
    pid_t pid_ = -1;
    int release_ = -1;
    bool held_ = false;
};

}  // namespace suite::test
