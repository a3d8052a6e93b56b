#pragma once
// The machinery shared by the STREAM-like kernels a = f(b, c). Each kernel file defines one
// Op (its formula, as data and as code) and registers StreamKernel<Op>; this header supplies
// the loops for every access pattern, first touch, the non-temporal-store loop and the check.
//
// Patterns (every one a permutation of 0..n-1, so each element is written exactly once per
// repetition and the same check works for all):
//   sequential  for i:            a[i]    = f(b[i], c[i])
//   random      for i:            a[p[i]] = f(b[p[i]], c[p[i]])   p: seeded uniform shuffle (uint32)
//   strided:S   for r < S, t < n/S: j = t*S + r; a[j] = f(b[j], c[j])   (n rounded down to a multiple of S)
#include <immintrin.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <random>
#include <string>

#include "harness/kernel.hpp"
#include "harness/units.hpp"

namespace suite::stream {

// Initial values: exact in binary floating point, and different for neighbouring elements, so
// that a kernel which reads the wrong element (or writes nothing) fails verification.
inline double init_b(std::uint64_t i) { return 1.0 + static_cast<double>(i % 1000) * 0.5; }
inline double init_c(std::uint64_t i) { return 2.0 + static_cast<double>(i % 777) * 0.25; }
constexpr double init_a = -1.0;
constexpr double scalar = 3.0;  // the s of scale and triad
constexpr double line_bytes = 64.0;

// A seeded uniformly random permutation of 0..n-1 (Fisher-Yates with a fixed generator, so the
// same seed gives the same permutation on every machine). Filled into already-touched memory.
void shuffled_permutation(std::uint32_t* p, std::uint64_t n, std::uint64_t seed);

// Registers StreamKernel<Op>; called from each kernel's own file.
template <class Op>
bool register_stream_kernel();

template <class Op>
void nt_store_loop(double* __restrict a, const double* __restrict b, const double* __restrict c, std::uint64_t n);

template <class Op>
class StreamKernel final : public Kernel {
public:
    explicit StreamKernel(const KernelConfig& cfg) : cfg_(cfg) {}

    static constexpr int arrays() { return 1 + Op::reads; }

    void setup(Arena& arena) override {
        const bool indexed = cfg_.access.name == "random";
        const double per_element = 8.0 * arrays() + (indexed ? 4.0 : 0.0);
        n_ = static_cast<std::uint64_t>(static_cast<double>(cfg_.size) / per_element);
        if (cfg_.access.name == "strided") n_ -= n_ % cfg_.access.stride;
        if (n_ == 0) throw UsageError("size " + format_bytes(cfg_.size) + " is too small for " + std::string(Op::name) + " " + cfg_.access.label());
        if (indexed && n_ > UINT32_MAX) throw UsageError("size too large for the 32-bit index array of the random pattern");
        a_ = arena.allocate<double>("a", n_);
        b_ = arena.allocate<double>("b", n_);
        if (Op::reads > 1) c_ = arena.allocate<double>("c", n_);
        if (indexed) p_ = arena.allocate<std::uint32_t>("index", n_);
        double* __restrict a = a_;
        double* __restrict b = b_;
        double* __restrict c = c_;
        std::uint32_t* __restrict p = p_;
        const std::int64_t n = static_cast<std::int64_t>(n_);
        // First touch: the same static schedule over i as the sequential loop, so with
        // placement=local each thread's block of every array lands on that thread's node.
#pragma omp parallel for schedule(static)
        for (std::int64_t i = 0; i < n; ++i) {
            a[i] = init_a;
            b[i] = init_b(static_cast<std::uint64_t>(i));
            if (Op::reads > 1) c[i] = init_c(static_cast<std::uint64_t>(i));
            if (p) p[i] = 0;
        }
        if (p) shuffled_permutation(p, n_, cfg_.seed);
    }

    void run() override {
        const std::string& pattern = cfg_.access.name;
        if constexpr (Op::has_nt) {
            if (cfg_.variant == "nt") return nt_store_loop<Op>(a_, b_, c_, n_);
        }
        if (pattern == "sequential") run_sequential(a_, b_, c_, n_);
        else if (pattern == "random") run_random(a_, b_, c_, p_, n_);
        else run_strided(a_, b_, c_, n_, cfg_.access.stride);
    }

    Verification verify() override {
        Verification v;
        const std::int64_t n = static_cast<std::int64_t>(n_);
        double max_err = 0;
        std::int64_t first_bad = -1;
#pragma omp parallel for schedule(static) reduction(max : max_err)
        for (std::int64_t i = 0; i < n; ++i) {
            const double expect = Op::apply(init_b(i), Op::reads > 1 ? init_c(i) : 0.0);
            const double err = std::fabs(a_[i] - expect);
            if (err > Op::tolerance * std::max(1.0, std::fabs(expect))) {
#pragma omp critical
                if (first_bad < 0 || i < first_bad) first_bad = i;
            }
            max_err = std::max(max_err, err);
        }
        v.max_error = max_err;
        v.passed = first_bad < 0;
        v.detail = "every a[i] against " + std::string(Op::formula) + " of the initial b, c";
        if (!v.passed) {
            const std::uint64_t i = static_cast<std::uint64_t>(first_bad);
            v.detail += "; first mismatch at i=" + std::to_string(i) + ": got " + std::to_string(a_[i]) + ", expected " +
                        std::to_string(Op::apply(init_b(i), Op::reads > 1 ? init_c(i) : 0.0));
        }
        return v;
    }

    Work work() const override {
        const double n = static_cast<double>(n_);
        const double accesses_read = Op::reads, accesses_written = 1;
        Work w;
        w.units = n;
        w.stream_bytes = n * 8.0 * (accesses_read + accesses_written);
        w.flops = n * Op::flops;
        // A store to a line not in cache first reads it (write-allocate) unless it is non-temporal.
        const double store_cost = cfg_.variant == "nt" ? 1.0 : 2.0;
        double granule = 8.0;  // bytes the memory system moves per access
        if (cfg_.access.name == "random") granule = line_bytes;
        if (cfg_.access.name == "strided") granule = std::min(line_bytes, 8.0 * static_cast<double>(cfg_.access.stride));
        w.hardware_bytes = n * granule * (accesses_read + accesses_written * store_cost);
        if (p_) w.hardware_bytes += n * 4.0;  // the index array, read sequentially
        w.footprint_bytes = n_ * (8ULL * arrays() + (p_ ? 4 : 0));
        return w;
    }

private:
    static void run_sequential(double* __restrict a, const double* __restrict b, const double* __restrict c, std::uint64_t n_) {
        const std::int64_t n = static_cast<std::int64_t>(n_);
#pragma omp parallel for schedule(static)
        for (std::int64_t i = 0; i < n; ++i) a[i] = Op::apply(b[i], Op::reads > 1 ? c[i] : 0.0);
    }
    static void run_random(double* __restrict a, const double* __restrict b, const double* __restrict c,
                           const std::uint32_t* __restrict p, std::uint64_t n_) {
        const std::int64_t n = static_cast<std::int64_t>(n_);
#pragma omp parallel for schedule(static)
        for (std::int64_t i = 0; i < n; ++i) {
            const std::uint32_t j = p[i];
            a[j] = Op::apply(b[j], Op::reads > 1 ? c[j] : 0.0);
        }
    }
    static void run_strided(double* __restrict a, const double* __restrict b, const double* __restrict c, std::uint64_t n_,
                            std::uint64_t stride) {
        const std::int64_t s = static_cast<std::int64_t>(stride);
        const std::int64_t rows = static_cast<std::int64_t>(n_) / s;
#pragma omp parallel for collapse(2) schedule(static)
        for (std::int64_t r = 0; r < s; ++r)
            for (std::int64_t t = 0; t < rows; ++t) {
                const std::int64_t j = t * s + r;
                a[j] = Op::apply(b[j], Op::reads > 1 ? c[j] : 0.0);
            }
    }

    KernelConfig cfg_;
    std::uint64_t n_ = 0;
    double* a_ = nullptr;
    double* b_ = nullptr;
    double* c_ = nullptr;
    std::uint32_t* p_ = nullptr;
};

// Non-temporal stores: the widest streaming store the build targets, after a scalar prologue
// that brings a[] to a vector boundary; each thread fences its own stores before the barrier.
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

// The loop body is Op::apply on whole vectors (GCC vector arithmetic, scalar operands broadcast).
template <class Op>
__attribute__((noinline)) void nt_store_loop(double* __restrict a, const double* __restrict b, const double* __restrict c,
                                             std::uint64_t n_) {
    const std::int64_t n = static_cast<std::int64_t>(n_);
#pragma omp parallel
    {
        const int nt = omp_get_num_threads(), t = omp_get_thread_num();
        const std::int64_t lo = n * t / nt, hi = n * (t + 1) / nt;
        std::int64_t i = lo;
        for (; i < hi && (reinterpret_cast<std::uintptr_t>(a + i) % sizeof(ntvec)) != 0; ++i)
            a[i] = Op::apply(b[i], Op::reads > 1 ? c[i] : 0.0);
        for (; i + nt_width <= hi; i += nt_width) {
            const ntvec vb = nt_load(b + i);
            const ntvec vc = Op::reads > 1 ? nt_load(c + i) : vb;
            nt_store(a + i, Op::apply(vb, vc));
        }
        for (; i < hi; ++i) a[i] = Op::apply(b[i], Op::reads > 1 ? c[i] : 0.0);
        _mm_sfence();
    }
}

template <class Op>
bool register_stream_kernel() {
    KernelEntry e;
    e.info.name = Op::name;
    e.info.group = "stream";
    e.info.formula = Op::formula;
    e.info.unit = "element";
    e.info.axis = AccessAxis::pattern;
    e.info.accesses = {"sequential", "random", "strided"};
    e.info.variants = Op::has_nt ? std::vector<std::string>{"", "nt"} : std::vector<std::string>{""};
    e.info.size_kind = SizeKind::bytes;
    e.info.metric = Metric::bandwidth;
    e.info.read_bytes_per_unit = 8.0 * Op::reads;
    e.info.write_bytes_per_unit = 8.0;
    e.info.flops_per_unit = Op::flops;
    e.info.notes = Op::notes;
    e.make = [](const KernelConfig& cfg) { return std::make_unique<StreamKernel<Op>>(cfg); };
    e.min_size_per_thread = 64;  // a couple of elements of every array
    return register_kernel(std::move(e));
}

}  // namespace suite::stream
