// ref_stream: the sequential stream kernels as a user would otherwise get them, the peers that
// `make bench-vs` (bench/vs_peers.py) holds the suite's stream kernels against:
//
//   stream-copy, stream-scale, stream-add, stream-triad   STREAM's loops as stream.c writes them:
//       `#pragma omp parallel for` over whole arrays, compiled as STREAM's users build it
//       (gcc -O3 -march=native -fopenmp, set by CMake for this target alone). GCC turns the copy
//       loop into a memcpy call per thread's chunk, as it does in stream.c.
//   memcpy    each thread memcpy()s its static block of b to a: glibc's copy, whatever it picks
//             for the size (rep movsb, vector loops, non-temporal stores above its threshold)
//   memset    each thread memset()s its static block of a: glibc's fill, the peer of `store`
//
// Sizes as the suite's: the footprint of all arrays together (2 for copy, scale and memcpy, 3 for
// add and triad, 1 for memset), split in whole cache lines between the threads. Bytes by the
// STREAM convention: 8 B per element of every array. Timing as bench/ref_random.cpp (a warm-up
// call, samples of at least 1 ms, at least 5 samples and 0.2 s); every result is checked.
//
//   ref_stream KERNELS SIZE_BYTES THREADS
// Prints one JSON object per kernel and line: kernel, size_bytes, threads, samples, calls,
// gbps_median, gbps_best, verified.
#include <omp.h>

#include "ref_common.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

namespace {

using ref::Timing;

double* fresh(std::size_t n) { return ref::fresh<double>(n); }

void report(const std::string& kernel, std::uint64_t size, int threads, const Timing& timing, double bytes, bool ok) {
    const std::vector<double>& t = timing.per_call;
    const double med = ref::median(t), best = *std::min_element(t.begin(), t.end());
    std::printf(
        "{\"kernel\": \"%s\", \"size_bytes\": %llu, \"threads\": %d, \"samples\": %zu, \"calls\": %d, \"gbps_median\": "
        "%.6g, "
        "\"gbps_best\": %.6g, \"verified\": %s}\n",
        kernel.c_str(), static_cast<unsigned long long>(size), threads, t.size(), timing.calls, bytes / med / 1e9,
        bytes / best / 1e9, ok ? "true" : "false");
    std::fflush(stdout);
}

// Each thread's block [lo, hi) of n elements, in whole 64 B lines, as the suite splits.
void block(std::int64_t n, std::int64_t& lo, std::int64_t& hi) {
    const std::int64_t lines = (n + 7) / 8, t = omp_get_thread_num(), nt = omp_get_num_threads();
    lo = std::min(n, lines * t / nt * 8);
    hi = std::min(n, lines * (t + 1) / nt * 8);
}

// STREAM's four loops, as stream.c writes them (scalar 3.0).
template <int Kernel>
void stream_loop(const char* name, std::uint64_t size, int threads) {
    constexpr int arrays = Kernel >= 2 ? 3 : 2;
    const auto n = static_cast<std::int64_t>(size / (8 * arrays));
    double *a = fresh(n), *b = fresh(n), *c = arrays == 3 ? fresh(n) : nullptr;
#pragma omp parallel for
    for (std::int64_t j = 0; j < n; ++j) {
        a[j] = -1.0;
        b[j] = 1.0 + static_cast<double>(j % 1000) * 0.5;
        if (c) c[j] = 2.0 + static_cast<double>(j % 777) * 0.25;
    }
    const double scalar = 3.0;
    const Timing t = ref::time_it([&](int k) {
        for (int r = 0; r < k; ++r) {
            if constexpr (Kernel == 0) {
#pragma omp parallel for
                for (std::int64_t j = 0; j < n; j++) a[j] = b[j];
            } else if constexpr (Kernel == 1) {
#pragma omp parallel for
                for (std::int64_t j = 0; j < n; j++) a[j] = scalar * b[j];
            } else if constexpr (Kernel == 2) {
#pragma omp parallel for
                for (std::int64_t j = 0; j < n; j++) a[j] = b[j] + c[j];
            } else {
#pragma omp parallel for
                for (std::int64_t j = 0; j < n; j++) a[j] = b[j] + scalar * c[j];
            }
        }
    });
    bool ok = true;
    for (std::int64_t j = 0; j < n && ok; ++j) {
        const double bj = 1.0 + static_cast<double>(j % 1000) * 0.5, cj = 2.0 + static_cast<double>(j % 777) * 0.25;
        const double want = Kernel == 0 ? bj : Kernel == 1 ? scalar * bj : Kernel == 2 ? bj + cj : bj + scalar * cj;
        ok = a[j] == want;
    }
    report(name, size, threads, t, 8.0 * arrays * static_cast<double>(n), ok);
    std::free(a), std::free(b), std::free(c);
}

void memcpy_blocks(std::uint64_t size, int threads) {
    const auto n = static_cast<std::int64_t>(size / 16);
    double *a = fresh(n), *b = fresh(n);
#pragma omp parallel
    {
        std::int64_t lo, hi;
        block(n, lo, hi);
        for (std::int64_t j = lo; j < hi; ++j) a[j] = -1.0, b[j] = 1.0 + static_cast<double>(j % 1000) * 0.5;
    }
    const Timing t = ref::time_it([&](int k) {
#pragma omp parallel
        {
            std::int64_t lo, hi;
            block(n, lo, hi);
            for (int r = 0; r < k; ++r) {
                std::memcpy(a + lo, b + lo, static_cast<std::size_t>(hi - lo) * sizeof(double));
                asm volatile("" ::: "memory");
            }
        }
    });
    bool ok = std::memcmp(a, b, static_cast<std::size_t>(n) * sizeof(double)) == 0;
    report("memcpy", size, threads, t, 16.0 * static_cast<double>(n), ok);
    std::free(a), std::free(b);
}

void memset_blocks(std::uint64_t size, int threads) {
    const auto n = static_cast<std::int64_t>(size / 8);
    double* a = fresh(n);
    unsigned char* bytes = reinterpret_cast<unsigned char*>(a);
#pragma omp parallel
    {
        std::int64_t lo, hi;
        block(n, lo, hi);
        for (std::int64_t j = lo; j < hi; ++j) a[j] = -1.0;
    }
    std::uint64_t done = 0;
    const Timing t = ref::time_it([&](int k) {
#pragma omp parallel
        {
            std::int64_t lo, hi;
            block(n, lo, hi);
            for (int r = 0; r < k; ++r) {
                std::memset(a + lo, static_cast<int>(1 + (done + r) % 255),
                            static_cast<std::size_t>(hi - lo) * sizeof(double));
                asm volatile("" ::: "memory");
            }
        }
        done += k;
    });
    const auto last = static_cast<unsigned char>(1 + (done - 1) % 255);
    bool ok = true;
    for (std::int64_t j = 0; j < n * 8 && ok; ++j) ok = bytes[j] == last;
    report("memset", size, threads, t, 8.0 * static_cast<double>(n), ok);
    std::free(a);
}

}  // namespace

int main(int argc, char** argv) {
    return ref::run_kernels(argc, argv, "ref_stream", "stream-copy,stream-scale,stream-add,stream-triad,memcpy,memset",
                            [](const std::string& k, std::uint64_t size, int threads) {
                                if (k == "stream-copy")
                                    stream_loop<0>("stream-copy", size, threads);
                                else if (k == "stream-scale")
                                    stream_loop<1>("stream-scale", size, threads);
                                else if (k == "stream-add")
                                    stream_loop<2>("stream-add", size, threads);
                                else if (k == "stream-triad")
                                    stream_loop<3>("stream-triad", size, threads);
                                else if (k == "memcpy")
                                    memcpy_blocks(size, threads);
                                else if (k == "memset")
                                    memset_blocks(size, threads);
                                else
                                    return false;
                                return true;
                            });
}
