// ref_random: the suite's random-pattern kernels written as the plain OpenMP loops anyone would
// write, with none of the suite's machinery (no registry, runner, arena, templates): the
// reference that `make bench-vs` holds the suite's random kernels against. Built by CMake with
// the suite's own flags. Same sizes (the footprint of all arrays, 4-byte indices included), same
// permutation (a seeded Fisher-Yates shuffle with std::mt19937_64 and a multiply-shift bound),
// same pointer-chase cycles, same timing rule (a warm-up call, samples of at least 1 ms, at least
// 5 samples and 0.2 s), and every result checked.
//
//   ref_random KERNELS SIZE_BYTES THREADS      KERNELS: a comma list of copy, scale, add, triad,
//                                              sin-add, load, store, latency
// Prints one JSON object per kernel and line: kernel, size_bytes, threads, samples, calls per
// sample, gbps_median and gbps_best (STREAM bytes: 8 B per array element read or written) or
// ns_median and ns_best (per dependent load), and verified.
#include <omp.h>

#include "ref_common.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

namespace {

using ref::fresh;
using ref::median;
using ref::time_it;
using ref::Timing;

double b_at(std::uint64_t i) { return 1.0 + static_cast<double>(i % 1000) * 0.5; }
double c_at(std::uint64_t i) { return 2.0 + static_cast<double>(i % 777) * 0.25; }

// The permutation: i-th step swaps p[i] with a uniformly drawn p[j], j <= i, from the top down.
void permutation(std::uint32_t* p, std::uint64_t n, std::uint64_t seed) {
    for (std::uint64_t i = 0; i < n; ++i) p[i] = static_cast<std::uint32_t>(i);
    std::mt19937_64 rng(seed);
    for (std::uint64_t i = n - 1; i > 0; --i) {
        const auto j = static_cast<std::uint64_t>((static_cast<unsigned __int128>(rng()) * (i + 1)) >> 64);
        std::swap(p[i], p[j]);
    }
}

void report(const std::string& kernel, std::uint64_t size, int threads, const Timing& t, double bytes_or_loads,
            bool latency, bool ok) {
    const double med = median(t.per_call), best = *std::min_element(t.per_call.begin(), t.per_call.end());
    if (latency)
        std::printf(
            "{\"kernel\": \"%s\", \"size_bytes\": %llu, \"threads\": %d, \"samples\": %zu, \"calls\": %d, "
            "\"ns_median\": %.6g, "
            "\"ns_best\": %.6g, \"verified\": %s}\n",
            kernel.c_str(), static_cast<unsigned long long>(size), threads, t.per_call.size(), t.calls,
            med / bytes_or_loads * 1e9, best / bytes_or_loads * 1e9, ok ? "true" : "false");
    else
        std::printf(
            "{\"kernel\": \"%s\", \"size_bytes\": %llu, \"threads\": %d, \"samples\": %zu, \"calls\": %d, "
            "\"gbps_median\": %.6g, "
            "\"gbps_best\": %.6g, \"verified\": %s}\n",
            kernel.c_str(), static_cast<unsigned long long>(size), threads, t.per_call.size(), t.calls,
            bytes_or_loads / med / 1e9, bytes_or_loads / best / 1e9, ok ? "true" : "false");
    std::fflush(stdout);
}

// a[p[i]] = f(b[p[i]], c[p[i]]) for copy, scale, add, triad, sin-add.
template <int Reads, class F>
void stream_kernel(const std::string& name, std::uint64_t size, int threads, F f) {
    const auto n = static_cast<std::int64_t>(size / (8 * (1 + Reads) + 4));
    double* a = fresh<double>(n);
    double* b = fresh<double>(n);
    double* c = Reads > 1 ? fresh<double>(n) : nullptr;
    std::uint32_t* p = fresh<std::uint32_t>(n);
#pragma omp parallel for schedule(static)
    for (std::int64_t i = 0; i < n; ++i) {
        a[i] = -1.0;
        b[i] = b_at(i);
        if (c) c[i] = c_at(i);
        p[i] = 0;
    }
    permutation(p, n, 1);
    const Timing t = time_it([&](int calls) {
#pragma omp parallel
        for (int k = 0; k < calls; ++k) {
#pragma omp for schedule(static)
            for (std::int64_t i = 0; i < n; ++i) {
                const std::uint32_t j = p[i];
                a[j] = f(b[j], Reads > 1 ? c[j] : 0.0);
            }
        }
    });
    bool ok = true;
    for (std::int64_t i = 0; i < n && ok; ++i)
        ok = std::fabs(a[i] - f(b_at(i), Reads > 1 ? c_at(i) : 0.0)) <= 1e-13 * std::fabs(a[i]) + 1e-300;
    report(name, size, threads, t, 8.0 * (1 + Reads) * static_cast<double>(n), false, ok);
    std::free(a), std::free(b), std::free(c), std::free(p);
}

void load_kernel(std::uint64_t size, int threads) {
    const auto n = static_cast<std::int64_t>(size / 12);
    double* b = fresh<double>(n);
    std::uint32_t* p = fresh<std::uint32_t>(n);
#pragma omp parallel for schedule(static)
    for (std::int64_t i = 0; i < n; ++i) {
        b[i] = b_at(i);
        p[i] = 0;
    }
    permutation(p, n, 1);
    double sum = 0;
    int done = 0;
    const Timing t = time_it([&](int calls) {
#pragma omp parallel
        for (int k = 0; k < calls; ++k) {
#pragma omp for schedule(static) reduction(+ : sum)
            for (std::int64_t i = 0; i < n; ++i) sum += b[p[i]];
        }
        done += calls;
    });
    double once = 0;  // exact in any order: every partial sum is a multiple of 0.5 below 2^52
    for (std::int64_t i = 0; i < n; ++i) once += b_at(i);
    report("load", size, threads, t, 8.0 * static_cast<double>(n), false, sum == once * done);
    std::free(b), std::free(p);
}

void store_kernel(std::uint64_t size, int threads) {
    const auto n = static_cast<std::int64_t>(size / 12);
    double* a = fresh<double>(n);
    std::uint32_t* p = fresh<std::uint32_t>(n);
#pragma omp parallel for schedule(static)
    for (std::int64_t i = 0; i < n; ++i) {
        a[i] = -1.0;
        p[i] = 0;
    }
    permutation(p, n, 1);
    std::uint64_t call = 0;
    const Timing t = time_it([&](int calls) {
#pragma omp parallel
        for (int k = 0; k < calls; ++k) {
            const double v = 1.0 + static_cast<double>((call + k) % 4096);
#pragma omp for schedule(static)
            for (std::int64_t i = 0; i < n; ++i) a[p[i]] = v;
        }
        call += calls;
    });
    const double last = 1.0 + static_cast<double>((call - 1) % 4096);
    bool ok = true;
    for (std::int64_t i = 0; i < n && ok; ++i) ok = a[i] == last;
    report("store", size, threads, t, 8.0 * static_cast<double>(n), false, ok);
    std::free(a), std::free(p);
}

struct alignas(64) Line {
    Line* next;
    char pad[56];
};

void latency_kernel(std::uint64_t size, int threads) {
    const std::uint64_t per = size / 64 / static_cast<std::uint64_t>(threads);
    Line* lines = fresh<Line>(per * threads);
    std::vector<Line*> start(threads), pos(threads);
#pragma omp parallel
    {
        const int t = omp_get_thread_num();
        Line* base = lines + per * t;
        std::vector<std::uint64_t> order(per);
        for (std::uint64_t k = 0; k < per; ++k) order[k] = k;
        std::mt19937_64 rng(1 * 1000003u + static_cast<std::uint64_t>(t));
        for (std::uint64_t i = per - 1; i > 0; --i) {
            const auto j = static_cast<std::uint64_t>((static_cast<unsigned __int128>(rng()) * (i + 1)) >> 64);
            std::swap(order[i], order[j]);
        }
        for (std::uint64_t k = 0; k < per; ++k) base[order[k]].next = &base[order[(k + 1) % per]];
        start[t] = pos[t] = &base[order[0]];
    }
    std::uint64_t calls_done = 0;
    const Timing t = time_it([&](int calls) {
#pragma omp parallel
        {
            const int me = omp_get_thread_num();
            Line* q = pos[me];
            for (int k = 0; k < calls; ++k)
                for (std::uint64_t s = 0; s <= per; ++s) q = q->next;
            pos[me] = q;
        }
        calls_done += calls;
    });
    // Each thread stands calls_done steps (mod the cycle) after its start.
    bool ok = true;
    for (int th = 0; th < threads; ++th) {
        const Line* q = start[th];
        for (std::uint64_t s = 0; s < calls_done % per; ++s) q = q->next;
        ok = ok && q == pos[th];
    }
    report("latency", size, threads, t, static_cast<double>(per + 1), true, ok);
    std::free(lines);
}

}  // namespace

int main(int argc, char** argv) {
    return ref::run_kernels(argc, argv, "ref_random", "copy,scale,add,triad,sin-add,load,store,latency",
                            [](const std::string& k, std::uint64_t size, int threads) {
                                if (k == "copy")
                                    stream_kernel<1>(k, size, threads, [](double b, double) { return b; });
                                else if (k == "scale")
                                    stream_kernel<1>(k, size, threads, [](double b, double) { return 3.0 * b; });
                                else if (k == "add")
                                    stream_kernel<2>(k, size, threads, [](double b, double c) { return b + c; });
                                else if (k == "triad")
                                    stream_kernel<2>(k, size, threads, [](double b, double c) { return b + 3.0 * c; });
                                else if (k == "sin-add")
                                    stream_kernel<2>(k, size, threads,
                                                     [](double b, double c) { return std::sin(b) + std::sin(c); });
                                else if (k == "load")
                                    load_kernel(size, threads);
                                else if (k == "store")
                                    store_kernel(size, threads);
                                else if (k == "latency")
                                    latency_kernel(size, threads);
                                else
                                    return false;
                                return true;
                            });
}
