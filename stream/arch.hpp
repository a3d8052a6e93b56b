#pragma once
// What the stream loops take from the instruction set, one block per architecture, so that the
// loops themselves (stream_kernel.hpp, store.cpp, load.cpp) are written once:
//   ntvec, nt_width       the vector the non-temporal loops compute on, in doubles
//   nt_load, nt_store     its load, and its streaming store (a store that does not keep the line)
//   nt_store_pair         two consecutive vectors streamed in one go
//   prefetch_read         a read prefetch into every level
//   nt_fence              what orders a thread's streaming stores before it leaves the loop
// and, on aarch64, whether the CPU runs SVE (read once from the kernel's HWCAP), for the loops
// that dispatch to their SVE twins at run time (one binary serves NEON-only and SVE CPUs).
//
//   x86-64   ntvec = the widest of __m512d / __m256d / __m128d the build targets; vmovntpd
//   aarch64  ntvec = float64x2_t (NEON); STNP of two q registers (the non-temporal pair store);
//            SVE loops stream with STNT1D, vector-length agnostic
#include <cstdint>

#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#elif defined(__aarch64__)
#include <arm_neon.h>
#include <sys/auxv.h>
#else
#error "suite's stream kernels are written for x86-64 and aarch64"
#endif

namespace suite::stream {

#if defined(__x86_64__) || defined(__i386__)
#if defined(__AVX512F__)
using ntvec = __m512d;
inline void nt_store(double* p, ntvec v) { _mm512_stream_pd(p, v); }
inline ntvec nt_load(const double* p) { return _mm512_loadu_pd(p); }
#elif defined(__AVX__)
using ntvec = __m256d;
inline void nt_store(double* p, ntvec v) { _mm256_stream_pd(p, v); }
inline ntvec nt_load(const double* p) { return _mm256_loadu_pd(p); }
#else
using ntvec = __m128d;
inline void nt_store(double* p, ntvec v) { _mm_stream_pd(p, v); }
inline ntvec nt_load(const double* p) { return _mm_loadu_pd(p); }
#endif
constexpr std::int64_t nt_width = sizeof(ntvec) / sizeof(double);
inline void nt_store_pair(double* p, ntvec v0, ntvec v1) {
    nt_store(p, v0);
    nt_store(p + nt_width, v1);
}
inline void prefetch_read(const void* p) { _mm_prefetch(static_cast<const char*>(p), _MM_HINT_T0); }
// Streaming stores are weakly ordered: sfence makes them visible before anything after it.
inline void nt_fence() { _mm_sfence(); }
inline bool cpu_has_sve() { return false; }

#elif defined(__aarch64__)
using ntvec = float64x2_t;
constexpr std::int64_t nt_width = 2;
inline ntvec nt_load(const double* p) { return vld1q_f64(p); }
// STNP stores a pair of registers with the hint that the data will not be read again soon: the
// Arm counterpart of vmovntpd. The q form stores 32 B, the d form one vector's two halves.
inline void nt_store_pair(double* p, ntvec v0, ntvec v1) {
    asm volatile("stnp %q0, %q1, [%2]" : : "w"(v0), "w"(v1), "r"(p) : "memory");
}
inline void nt_store(double* p, ntvec v) {
    asm volatile("stnp %d0, %d1, [%2]" : : "w"(vget_low_f64(v)), "w"(vget_high_f64(v)), "r"(p) : "memory");
}
inline void prefetch_read(const void* p) { __builtin_prefetch(p, 0, 3); }
// STNP needs no fence for the thread's own view; the store barrier orders the streamed lines
// before the team's join for the other threads, as sfence does on x86.
inline void nt_fence() { asm volatile("dmb ishst" ::: "memory"); }
inline bool cpu_has_sve() {
    static const bool sve = (getauxval(AT_HWCAP) & HWCAP_SVE) != 0;
    return sve;
}
#endif

}  // namespace suite::stream

// The SVE twins: functions marked SUITE_SVE are compiled for SVE whatever the build's -march,
// and called only where cpu_has_sve() says the CPU runs them.
#if defined(__aarch64__)
#pragma GCC push_options
#pragma GCC target("+sve")
#include <arm_sve.h>
#pragma GCC pop_options
#define SUITE_HAVE_SVE_TWINS 1
#define SUITE_SVE __attribute__((target("+sve")))
#else
#define SUITE_HAVE_SVE_TWINS 0
#endif
