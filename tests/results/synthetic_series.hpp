#pragma once
// A made-up history for the dashboard's tests (tests/results/dashboard_test.cpp and the browser
// test's tests/browser/dashboard_fixture.cpp): two machines, five series of 24 runs each, with
// noise, an unstable run, steps that are worse and better in both directions of "better", and a
// context string that tries to close the page's script element. Deterministic: no random numbers.
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "harness/results/history_series.hpp"

namespace suite::test {

inline constexpr std::size_t synthetic_runs = 24;
inline constexpr const char* hostile_context = "THP always, -O3 </script><script>document.title='pwned'</script><!--";

// The commit of run i: twelve hex digits, the same for every series (one build ran them all).
inline std::string synthetic_commit(std::size_t i) {
    char buf[16];
    std::snprintf(buf, sizeof buf, "%012llx",
                  static_cast<unsigned long long>((0x9e3779b97f4aULL * (i + 7)) & 0xffffffffffffULL));
    return buf;
}

inline PointKey synthetic_key(const std::string& kernel, const std::string& access, std::uint64_t size, int threads) {
    PointKey k;
    k.kernel = kernel;
    k.access = access;
    k.size_kind = "bytes";
    k.size = size;
    k.threads = threads;
    k.pin = "compact";
    k.placement = "local";
    return k;
}

// Levels: the median is `level` until each step's index, then multiplied by the step's factor.
struct SyntheticShape {
    double level;
    double noise;
    std::vector<std::pair<std::size_t, double>> steps;  // (first index of the new level, factor)
};

inline Series synthetic_one(const std::string& machine, const std::string& fingerprint, PointKey key,
                            const std::string& figure, const std::string& unit, Direction direction,
                            const SyntheticShape& shape, std::int64_t first_run) {
    Series s;
    s.machine = machine;
    s.fingerprint = fingerprint;
    s.context_class = "THP madvise, -O3 -march=native";
    s.key = std::move(key);
    s.figure = figure;
    s.unit = unit;
    s.direction = direction;
    double level = shape.level;
    std::size_t next = 0;
    for (std::size_t i = 0; i < synthetic_runs; ++i) {
        if (next < shape.steps.size() && shape.steps[next].first == i) {
            const double before = level;
            level *= shape.steps[next].second;
            Step st;
            st.index = i;
            st.commit = synthetic_commit(i);
            st.before = before;
            st.after = level;
            st.change = level / before - 1;
            st.p = 0.0004 * static_cast<double>(next + 1);
            st.worse = (direction == Direction::higher_is_better) == (level < before);
            s.steps.push_back(st);
            ++next;
        }
        SeriesEntry e;
        e.commit = synthetic_commit(i) + (i + 1 == synthetic_runs ? "-dirty" : "");
        e.branch = i % 5 == 3 ? "topic/prefetch" : "main";
        char date[32];
        std::snprintf(date, sizeof date, "2025-03-%02zuT04:%02zu:00Z", i + 1, (i * 7) % 60);
        e.date = date;
        e.run_id = first_run + static_cast<std::int64_t>(i);
        e.median =
            level * (1 + 0.6 * shape.noise * std::sin(1.7 * static_cast<double>(i) + static_cast<double>(first_run)));
        e.noise = shape.noise * (1 + 0.3 * std::cos(static_cast<double>(i)));
        e.samples = {e.median * (1 - e.noise), e.median, e.median * (1 + e.noise)};
        e.unstable = i == 9;
        s.entries.push_back(e);
    }
    return s;
}

inline std::vector<Series> synthetic_history() {
    const std::string a = "ci-runner (AMD EPYC 7763 64-Core Processor, 4 cores)", fa = "3f9a0c1d77e2b410";
    const std::string b = "lab-2s (Intel Xeon Gold 6338, 64 cores)", fb = "c05e4d1a9b8f6e23";
    std::vector<Series> out;
    out.push_back(synthetic_one(a, fa, synthetic_key("add", "random", 64 << 10, 2), "bandwidth", "GB/s",
                                Direction::higher_is_better, {41.0, 0.02, {{14, 0.85}}}, 100));
    out.push_back(synthetic_one(a, fa, synthetic_key("triad", "sequential", 1ULL << 30, 1), "bandwidth", "GB/s",
                                Direction::higher_is_better, {12.4, 0.03, {}}, 200));
    out.push_back(synthetic_one(a, fa, synthetic_key("add", "random", 64ULL << 20, 1), "latency", "ns/load",
                                Direction::lower_is_better, {92.0, 0.015, {{8, 0.8}}}, 300));
    out.push_back(synthetic_one(b, fb, synthetic_key("triad", "sequential", 1ULL << 30, 16), "bandwidth", "GB/s",
                                Direction::higher_is_better, {96.0, 0.025, {{6, 0.9}, {17, 1.25}}}, 400));
    Series hostile = synthetic_one(b, fb, synthetic_key("copy", "strided:8", 16ULL << 20, 4), "bandwidth", "GB/s",
                                   Direction::higher_is_better, {31.0, 0.04, {}}, 500);
    hostile.context_class = hostile_context;
    out.push_back(hostile);
    return out;
}

}  // namespace suite::test
