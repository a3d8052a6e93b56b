#pragma once
// How a kernel splits its iterations over the OpenMP team. First touch, the timed loops and
// verify() take the same split from here, so that "the pages a thread computes on are the
// pages it touched first" holds by construction rather than by what an OpenMP runtime does.
#include <omp.h>

#include <algorithm>
#include <cstdint>

namespace suite {

// Thread t's share [lo, hi) of n iterations split over nt threads: contiguous blocks, the
// first n % nt threads one longer. The application kernels (kernels/sfc) split their elements
// and vertices this way, and the sfc quality figures are defined by it.
struct Block {
    std::int64_t lo, hi;
};
inline Block static_block(std::int64_t n, int t, int nt) {
    const std::int64_t q = n / nt, r = n % nt;
    const std::int64_t lo = t * q + std::min<std::int64_t>(t, r);
    return {lo, lo + q + (t < r ? 1 : 0)};
}
inline Block my_block(std::int64_t n) { return static_block(n, omp_get_thread_num(), omp_get_num_threads()); }

// The stream kernels' split: contiguous blocks whose inner boundaries fall on whole cache lines
// (multiples of 8 doubles), so that no two threads write the same line and each block of a
// page-aligned array starts on a vector boundary; the blocks differ by at most 8 elements (a
// thread's block may be empty when n < 8 x threads). First touch, every loop and verify() use
// it, so "the same schedule" holds by construction rather than by what an OpenMP runtime
// happens to do.
constexpr std::int64_t block_grain = 8;
inline Block line_block(std::int64_t n, int t, int nt) {
    auto boundary = [&](int k) {
        if (k >= nt) return n;
        const auto exact = static_cast<std::int64_t>(static_cast<__int128>(n) * k / nt);
        return exact / block_grain * block_grain;
    };
    return {boundary(t), boundary(t + 1)};
}
inline Block my_line_block(std::int64_t n) { return line_block(n, omp_get_thread_num(), omp_get_num_threads()); }

}  // namespace suite
