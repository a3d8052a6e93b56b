#pragma once
// What the reference programs of `make bench-vs` (ref_random, ref_stream) share: allocation, the
// suite's timing rule, the median, and the command line `PROGRAM KERNELS SIZE_BYTES THREADS`.
#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

namespace ref {

using Clock = std::chrono::steady_clock;

// Page-aligned memory for n elements; a failure ends the program.
template <class T>
T* fresh(std::size_t n) {
    void* p = std::aligned_alloc(4096, (n * sizeof(T) + 4095) / 4096 * 4096);
    if (!p) {
        std::fprintf(stderr, "out of memory\n");
        std::exit(1);
    }
    return static_cast<T*>(p);
}

struct Timing {
    std::vector<double> per_call;  // seconds per call, one per sample
    int calls = 1;
};

// Calls `run(calls)` as the suite's runner does: one warm-up call, then samples of `calls`
// calls each lasting at least 1 ms, until 0.2 s and at least 5 samples.
template <class Run>
Timing time_it(Run run) {
    Timing t;
    auto t0 = Clock::now();
    run(1);
    const double first = std::max(std::chrono::duration<double>(Clock::now() - t0).count(), 1e-9);
    t.calls = first >= 1e-3 ? 1 : static_cast<int>(std::ceil(1e-3 / first));
    const int samples = std::clamp(static_cast<int>(std::ceil(0.2 / (first * t.calls))), 5, 1000000);
    for (int s = 0; s < samples; ++s) {
        t0 = Clock::now();
        run(t.calls);
        t.per_call.push_back(std::chrono::duration<double>(Clock::now() - t0).count() / t.calls);
    }
    return t;
}

inline double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    const std::size_t m = v.size() / 2;
    return v.size() % 2 ? v[m] : (v[m - 1] + v[m]) / 2;
}

// `program KERNELS SIZE_BYTES THREADS`: runs `kernel(name, size, threads)` for each name of the
// comma list, which returns false for a name it does not know. Returns the exit status.
template <class Kernel>
int run_kernels(int argc, char** argv, const char* program, const char* names, Kernel kernel) {
    if (argc != 4) {
        std::fprintf(stderr, "usage: %s KERNELS SIZE_BYTES THREADS (KERNELS: %s)\n", program, names);
        return 2;
    }
    const std::uint64_t size = std::strtoull(argv[2], nullptr, 10);
    const int threads = std::atoi(argv[3]);
    if (size < 4096 || threads < 1) {
        std::fprintf(stderr, "%s: SIZE_BYTES must be at least 4096 and THREADS at least 1\n", program);
        return 2;
    }
    omp_set_num_threads(threads);
    const std::string list = argv[1];
    for (std::size_t from = 0; from <= list.size();) {
        const std::size_t comma = std::min(list.find(',', from), list.size());
        const std::string k = list.substr(from, comma - from);
        from = comma + 1;
        if (!kernel(k, size, threads)) {
            std::fprintf(stderr, "%s: unknown kernel '%s'\n", program, k.c_str());
            return 2;
        }
    }
    return 0;
}

}  // namespace ref
