#pragma once
// What SELL-C-σ (sell.hpp) takes from the instruction set, one block per architecture, so that the
// storage and its product are written once:
//   sell_c       C, the doubles of the build's vector: 8 with AVX-512F, 4 with AVX, 2 with SSE2 or NEON
//   sell_chunk   one chunk's C row sums, sums[r] = Σ_j val[C j + r] x[col[C j + r]] for j < width,
//                each lane's terms added in j order (its row's CSR order, then the padding zeros)
//
// One loop for every target: C independent lane sums, which the compiler keeps in registers and
// schedules (8 FMA or multiply-add chains with AVX-512). An AVX-512 gather loop (one vgatherdpd of
// 8 x a column) was measured first and ran 1.18 to 2.92 times CSR's time on the AMD EPYC VM, where
// this loop ran 0.75 to 0.93 times it (docs/kernels.md). Whether a lane's sum rounds as the CSR
// row does depends on whether the compiler contracts either loop into FMAs; verification allows
// for both (sell.cpp).
#include <cstdint>

namespace suite::fem {

#if defined(__x86_64__) && defined(__AVX512F__)
constexpr int sell_c = 8;
#elif defined(__x86_64__) && defined(__AVX__)
constexpr int sell_c = 4;
#else
constexpr int sell_c = 2;  // SSE2, NEON
#endif

// The width is the chunk's longest row; val and col hold width * C entries, column-major.
inline void sell_chunk(const double* __restrict val, const std::uint32_t* __restrict col, std::int64_t width,
                       const double* __restrict x, double* __restrict sums) {
    double s[sell_c] = {};
    for (std::int64_t j = 0; j < width; ++j)
        for (int r = 0; r < sell_c; ++r) s[r] += val[sell_c * j + r] * x[col[sell_c * j + r]];
    for (int r = 0; r < sell_c; ++r) sums[r] = s[r];
}

}  // namespace suite::fem
