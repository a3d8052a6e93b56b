#pragma once
// What SELL-C-σ (sell.hpp) takes from the instruction set, one block per architecture, so that the
// storage and its product are written once:
//   sell_c       C, the doubles of the build's vector: 8 with AVX-512F, 4 with AVX, 2 with SSE2 or NEON
//   sell_chunk   one chunk's C row sums, sums[r] = Σ_j val[C j + r] x[col[C j + r]] for j < width,
//                each lane's terms added in j order (its row's CSR order, then the padding zeros)
//
//   x86-64 AVX-512F  one vgatherdpd of 8 x, a multiply and an add a column of the chunk
//   elsewhere        a plain loop over the lanes, for the compiler to vectorise (gathers under AVX2,
//                    NEON's two lanes on aarch64): the same loop shape as the CSR row, so that a
//                    lane's sum rounds as the CSR row's does
#include <cstdint>

#if defined(__x86_64__) && defined(__AVX512F__)
#include <immintrin.h>
#endif

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
#if defined(__x86_64__) && defined(__AVX512F__)
    // Column indices are below 2^31 (sell.cpp refuses a larger matrix): the gather's signed indices.
    // A multiply and an add, not an FMA: GCC compiles the CSR row unfused where it tunes for AMD's
    // cores (it avoids FMA chains there), and then each lane rounds as the CSR row does. A build
    // that fuses the CSR row (Intel tuning) agrees with it to round-off instead.
    // The masked form with every lane set is the same vgatherdpd; the plain one's undefined source
    // register trips GCC 12's -Wmaybe-uninitialized.
    const __m512d zero = _mm512_setzero_pd();
    __m512d s = zero;
    for (std::int64_t j = 0; j < width; ++j) {
        const __m256i c = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(col + 8 * j));
        __m512d p = _mm512_mul_pd(_mm512_loadu_pd(val + 8 * j), _mm512_mask_i32gather_pd(zero, 0xFF, c, x, 8));
        __asm__("" : "+v"(p));  // the product rounded on its own: GCC would contract the two into an FMA
        s = _mm512_add_pd(s, p);
    }
    _mm512_storeu_pd(sums, s);
#else
    double s[sell_c] = {};
    for (std::int64_t j = 0; j < width; ++j)
        for (int r = 0; r < sell_c; ++r) s[r] += val[sell_c * j + r] * x[col[sell_c * j + r]];
    for (int r = 0; r < sell_c; ++r) sums[r] = s[r];
#endif
}

}  // namespace suite::fem
