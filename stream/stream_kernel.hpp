#pragma once
// The machinery shared by the STREAM-like kernels a = f(b, c). Each kernel file defines one
// Op (its formula, as data and as code) and registers StreamKernel<Op>; this header supplies
// the loops for every access pattern, first touch, the non-temporal-store loop, the string-
// instruction copy (rep movsb, copy's "rep" variant) and the check.
//
// Patterns (every one a permutation of 0..n-1, so each element is written exactly once per
// repetition and the same check works for all):
//   sequential  for i:                      a[i]    = f(b[i], c[i])
//   random      for i:                      a[p[i]] = f(b[p[i]], c[p[i]])   p: seeded uniform shuffle (uint32)
//   strided:S   in each thread's block [lo, hi): for r < S: for j = lo+r; j < hi; j += S: a[j] = f(b[j], c[j])
// Every thread works on the block of i that it first touched (line_block), so with
// placement=local the sequential and strided patterns only touch the thread's own pages; the
// random pattern reaches anywhere by design.
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <string>

#include "harness/common/units.hpp"
#include "harness/kernel/blocks.hpp"
#include "harness/kernel/kernel.hpp"
#include "harness/kernel/permutation.hpp"
#include "stream/arch.hpp"

namespace suite::stream {

// Initial values: exact in binary floating point, and different for neighbouring elements, so
// that a kernel which reads the wrong element (or writes nothing) fails verification.
inline double init_b(std::uint64_t i) { return 1.0 + static_cast<double>(i % 1000) * 0.5; }
inline double init_c(std::uint64_t i) { return 2.0 + static_cast<double>(i % 777) * 0.25; }
constexpr double init_a = -1.0;
constexpr double scalar = 3.0;  // the s of scale and triad
constexpr double line_bytes = 64.0;

// How far ahead (elements: 4 KiB) the nt loops of the one-read kernels (copy, scale) prefetch
// their source. Measured at 1 GiB on the 2-core Zen 5 VM, medians of 4-6 interleaved runs:
// copy-nt +14 % (1 thread, 32.4 -> 37.4 GB/s; 2 threads 49.2 -> 55.9), scale-nt +12-14 %,
// nothing at 1 MiB; 2 KiB ahead did as well. The two-read kernels (add, triad) gained nothing
// from prefetching both sources (1 thread: triad-nt 34.1 against 38.0, add-nt 36.7 against 36.5).
constexpr std::int64_t nt_prefetch = 512;

// The string instructions of the "rep" variants: one instruction copies (rep movsb) or fills
// (rep stosq) a thread's whole block, and the CPU's microcode picks the width, the alignment
// handling and, on a CPU with fast strings (ERMS), stores of whole lines that skip the read of
// the destination: what glibc's memcpy and memset do between a few KiB and their non-temporal
// threshold. The ABI guarantees the direction flag clear on entry to a function.
#if defined(__x86_64__)
constexpr bool have_string_ops = true;
constexpr const char* no_string_ops = "";
inline void rep_movsb(void* dst, const void* src, std::size_t bytes) {
    asm volatile("rep movsb" : "+D"(dst), "+S"(src), "+c"(bytes) : : "memory");
}
inline void rep_stosq(void* dst, std::uint64_t value, std::size_t words) {
    asm volatile("rep stosq" : "+D"(dst), "+c"(words) : "a"(value) : "memory");
}
#else
constexpr bool have_string_ops = false;  // the rep variants are not registered
constexpr const char* no_string_ops =
    "rep movsb and rep stosq are x86-64 string instructions; this build is not x86-64";
inline void rep_movsb(void*, const void*, std::size_t) {}
inline void rep_stosq(void*, std::uint64_t, std::size_t) {}
#endif

enum class Pattern { sequential, random, strided };
inline Pattern pattern_of(const Access& a) {
    return a.name == "random" ? Pattern::random : a.name == "strided" ? Pattern::strided : Pattern::sequential;
}

// Between two calls that need no barrier: the compiler must assume memory was read and changed,
// so it can neither merge the calls nor drop one whose stores are overwritten by the next.
inline void compiler_fence() { asm volatile("" ::: "memory"); }

// The barrier between two calls whose threads share data: none is needed by a team of one,
// where libgomp's barrier still costs a few hundred nanoseconds a call (a third of a call of
// random add at 32 KiB). Every thread of the team takes the same branch.
inline void barrier_between_calls() {
    if (omp_get_num_threads() > 1) {
#pragma omp barrier
    } else {
        compiler_fence();
    }
}

// Elements per unrolled step of the sequential loops: four 512-bit vectors, so that the loop
// overhead is shared by four loads (and stores) of each array.
constexpr std::int64_t unroll_elements = 32;

// The configuration checks of every stream kernel, run before anything is measured.
inline std::uint64_t stream_elements(const KernelConfig& cfg, int arrays) {
    const bool indexed = cfg.access.name == "random";
    return static_cast<std::uint64_t>(static_cast<double>(cfg.size) / (8.0 * arrays + (indexed ? 4.0 : 0.0)));
}
void validate_stream_config(const KernelConfig& cfg, const char* name, int arrays);

// First touch by the computing threads, each its own line block (the block it computes on), so
// that with placement=local each thread's block of every array lands on that thread's node.
// touch(i) writes element i of every array; the random pattern's index (nullptr for the other
// patterns) is touched the same way, then shuffled with the run's seed.
template <class Touch>
void first_touch(const KernelConfig& cfg, std::uint64_t elements, std::uint32_t* index, Touch touch) {
    const std::int64_t n = static_cast<std::int64_t>(elements);
    int team = 0;
#pragma omp parallel num_threads(cfg.threads) reduction(max : team)
    {
        team = omp_get_num_threads();
        const Block blk = my_line_block(n);  // first touch: this thread's block
        for (std::int64_t i = blk.lo; i < blk.hi; ++i) {
            touch(i);
            if (index) index[i] = 0;
        }
    }
    require_team_size(team, cfg.threads);
    if (index) shuffled_permutation(index, elements, cfg.seed);
}

// What one call of a streaming kernel moves: `reads` arrays read and `writes` written, n elements
// each. STREAM's count takes each access once, 8 B; the hardware estimate adds what the memory
// system really moves: a store to a line not in cache first reads it (write-allocate) unless it
// is non-temporal or a string instruction's (an estimate there: a CPU with fast strings stores
// whole lines of a large block, and says nothing), a scattered access moves its whole granule,
// and the random pattern reads its index array too.
inline Work stream_work(const KernelConfig& cfg, std::uint64_t elements, int reads, int writes, double flops) {
    const double n = static_cast<double>(elements);
    const double accesses_read = reads, accesses_written = writes;
    const Pattern pattern = pattern_of(cfg.access);
    const bool indexed = pattern == Pattern::random;
    Work w;
    w.units = n;
    w.stream_bytes = n * 8.0 * (accesses_read + accesses_written);
    w.flops = n * flops;
    const double store_cost = is_store_variant(cfg.variant) ? 1.0 : 2.0;
    double granule = 8.0;  // bytes the memory system moves per access
    if (pattern == Pattern::random) granule = line_bytes;
    if (pattern == Pattern::strided) granule = std::min(line_bytes, 8.0 * static_cast<double>(cfg.access.stride));
    w.hardware_bytes = n * granule * (accesses_read + accesses_written * store_cost);
    if (indexed) w.hardware_bytes += n * 4.0;  // the index array, read sequentially
    w.footprint_bytes = elements * (8ULL * static_cast<std::uint64_t>(reads + writes) + (indexed ? 4 : 0));
    return w;
}

template <class Op>
class StreamKernel final : public Kernel {
public:
    explicit StreamKernel(const KernelConfig& cfg) : cfg_(cfg) {}

    static constexpr int arrays() { return 1 + Op::reads; }

    void setup(Arena& arena) override {
        pattern_ = pattern_of(cfg_.access);
        stride_ = static_cast<std::int64_t>(cfg_.access.stride);
        n_ = stream_elements(cfg_, arrays());
        a_ = arena.allocate<double>("a", n_);
        b_ = arena.allocate<double>("b", n_);
        if (Op::reads > 1) c_ = arena.allocate<double>("c", n_);
        if (pattern_ == Pattern::random) p_ = arena.allocate<std::uint32_t>("index", n_);
        double* __restrict a = a_;
        double* __restrict b = b_;
        double* __restrict c = c_;
        first_touch(cfg_, n_, p_, [&](std::int64_t i) {
            a[i] = init_a;
            b[i] = init_b(static_cast<std::uint64_t>(i));
            if (Op::reads > 1) c[i] = init_c(static_cast<std::uint64_t>(i));
        });
    }

    // `calls` repetitions inside one parallel region. Where each thread reads and writes only
    // its own block (sequential, strided, nt), a thread's next call depends on nothing another
    // thread does, so the calls need no barrier between them (likwid-bench's threads run their
    // iterations the same way); the end of the region joins them. The random pattern writes
    // anywhere, so its calls are separated by barriers.
    void run(int calls) override {
        double* __restrict a = a_;
        const double* __restrict b = b_;
        const double* __restrict c = c_;
        const std::uint32_t* __restrict p = p_;
        const std::int64_t n = static_cast<std::int64_t>(n_), s = stride_;
        if constexpr (Op::has_nt) {
            if (cfg_.variant == "nt") {
#if SUITE_HAVE_SVE_TWINS
                if (cpu_has_sve()) return nt_store_loop_sve(a, b, c, n, calls);
#endif
                return nt_store_loop(a, b, c, n, calls);
            }
        }
        if constexpr (Op::has_rep) {
            if (cfg_.variant == "rep") return rep_copy_loop(a, b, n, calls);
        }
        switch (pattern_) {
            case Pattern::sequential:
#if SUITE_HAVE_SVE_TWINS
                if (cpu_has_sve()) return sequential_loop_sve(a, b, c, n, calls);
#endif
                return sequential_loop(a, b, c, n, calls);
            case Pattern::random:
                return random_loop(a, b, c, p, n, calls);
            case Pattern::strided:
                return strided_loop(a, b, c, n, s, calls);
        }
    }

    Verification verify() override {
        Verification v;
        const std::int64_t n = static_cast<std::int64_t>(n_);
        double max_err = 0;
        std::int64_t first_bad = n;
#pragma omp parallel for schedule(static) reduction(max : max_err) reduction(min : first_bad)
        for (std::int64_t i = 0; i < n; ++i) {
            const double expect = expected(static_cast<std::uint64_t>(i));
            const double err = std::fabs(a_[i] - expect);
            // Written so that a NaN result fails: every comparison with NaN is false.
            if (!(err <= Op::tolerance * std::max(1.0, std::fabs(expect)))) {
                first_bad = std::min(first_bad, i);
                // A NaN is recorded as the largest double: JSON has no NaN or infinity.
                max_err = std::max(max_err, std::isnan(err) ? std::numeric_limits<double>::max() : err);
            } else {
                max_err = std::max(max_err, err);
            }
        }
        v.max_error = max_err;
        v.passed = first_bad == n;
        v.detail = "every a[i] against " + std::string(Op::formula) + " of the initial b, c";
        if (!v.passed) {
            const auto i = static_cast<std::uint64_t>(first_bad);
            v.detail += "; first mismatch at i=" + std::to_string(i) + ": got " + std::to_string(a_[i]) +
                        ", expected " + std::to_string(expected(i));
        }
        return v;
    }

    Work work() const override { return stream_work(cfg_, n_, Op::reads, 1, Op::flops); }

private:
    static double expected(std::uint64_t i) { return Op::apply(init_b(i), Op::reads > 1 ? init_c(i) : 0.0); }

    // The body is unrolled by hand (an `omp simd` loop over a fixed 32 elements, which the
    // compiler turns into four vector operations of each kind) because GCC does not unroll a
    // vectorised loop at -O3, and the loop overhead of one vector per iteration costs a third
    // of the L1 bandwidth.
    __attribute__((noinline)) static void sequential_loop(double* __restrict a, const double* __restrict b,
                                                          const double* __restrict c, std::int64_t n, int calls) {
#pragma omp parallel
        {
            const Block blk = my_line_block(n);
            for (int k = 0; k < calls; ++k) {
                std::int64_t i = blk.lo;
                for (; i + unroll_elements <= blk.hi; i += unroll_elements) {
#pragma omp simd
                    for (std::int64_t j = i; j < i + unroll_elements; ++j)
                        a[j] = Op::apply(b[j], Op::reads > 1 ? c[j] : 0.0);
                }
                for (; i < blk.hi; ++i) a[i] = Op::apply(b[i], Op::reads > 1 ? c[i] : 0.0);
                compiler_fence();
            }
        }
    }
    static void random_loop(double* __restrict a, const double* __restrict b, const double* __restrict c,
                            const std::uint32_t* __restrict p, std::int64_t n, int calls) {
#pragma omp parallel
        {
            const Block blk = my_line_block(n);
            for (int k = 0; k < calls; ++k) {
                for (std::int64_t i = blk.lo; i < blk.hi; ++i) {
                    const std::uint32_t j = p[i];
                    a[j] = Op::apply(b[j], Op::reads > 1 ? c[j] : 0.0);
                }
                barrier_between_calls();
            }
        }
    }
    static void strided_loop(double* __restrict a, const double* __restrict b, const double* __restrict c,
                             std::int64_t n, std::int64_t s, int calls) {
#pragma omp parallel
        {
            const Block blk = my_line_block(n);
            for (int k = 0; k < calls; ++k) {
                for (std::int64_t r = 0; r < s; ++r)
                    for (std::int64_t j = blk.lo + r; j < blk.hi; j += s)
                        a[j] = Op::apply(b[j], Op::reads > 1 ? c[j] : 0.0);
                compiler_fence();
            }
        }
    }
    // A scalar prologue brings a[] to a vector boundary; the body is Op::apply on whole vectors
    // (GCC vector arithmetic, scalar operands broadcast) stored with streaming stores, two
    // vectors a step (four, all loads first as likwid-bench's stream_mem does, measured no
    // faster), with the source prefetched nt_prefetch ahead in the one-read kernels. Each thread
    // fences its own stores once, after its last call: a thread sees its own streaming stores in
    // order anyway, and a fence after every call waited for the write-combining buffers to
    // drain, which in cache cost a third of the bandwidth.
    __attribute__((noinline)) static void nt_store_loop(double* __restrict a, const double* __restrict b,
                                                        const double* __restrict c, std::int64_t n, int calls) {
#pragma omp parallel
        {
            const Block blk = my_line_block(n);
            for (int k = 0; k < calls; ++k) {
                std::int64_t i = blk.lo;
                for (; i < blk.hi && (reinterpret_cast<std::uintptr_t>(a + i) % sizeof(ntvec)) != 0; ++i)
                    a[i] = Op::apply(b[i], Op::reads > 1 ? c[i] : 0.0);
                for (; i + 2 * nt_width <= blk.hi; i += 2 * nt_width) {
                    if constexpr (Op::reads == 1)
                        for (std::int64_t l = 0; l < 2 * nt_width; l += 8) prefetch_read(b + i + l + nt_prefetch);
                    const ntvec vb0 = nt_load(b + i), vb1 = nt_load(b + i + nt_width);
                    const ntvec vc0 = Op::reads > 1 ? nt_load(c + i) : vb0;
                    const ntvec vc1 = Op::reads > 1 ? nt_load(c + i + nt_width) : vb1;
                    nt_store_pair(a + i, Op::apply(vb0, vc0), Op::apply(vb1, vc1));
                }
                for (; i < blk.hi; ++i) a[i] = Op::apply(b[i], Op::reads > 1 ? c[i] : 0.0);
                compiler_fence();
            }
            nt_fence();
        }
    }

#if SUITE_HAVE_SVE_TWINS
    // The SVE twins (aarch64 CPUs with SVE): the same loops, vector-length agnostic. The plain
    // loop is the compiler's (whilelo, ld1d, st1d: it vectorises a loop for SVE without the
    // hand unrolling the fixed-width loop needs); the nt loop streams each vector with STNT1D.
    __attribute__((noinline)) SUITE_SVE static void sequential_loop_sve(double* __restrict a,
                                                                        const double* __restrict b,
                                                                        const double* __restrict c, std::int64_t n,
                                                                        int calls) {
#pragma omp parallel
        {
            const Block blk = my_line_block(n);
            for (int k = 0; k < calls; ++k) {
                for (std::int64_t i = blk.lo; i < blk.hi; ++i) a[i] = Op::apply(b[i], Op::reads > 1 ? c[i] : 0.0);
                compiler_fence();
            }
        }
    }
    __attribute__((noinline)) SUITE_SVE static void nt_store_loop_sve(double* __restrict a, const double* __restrict b,
                                                                      const double* __restrict c, std::int64_t n,
                                                                      int calls) {
#pragma omp parallel
        {
            const Block blk = my_line_block(n);
            const std::int64_t step = static_cast<std::int64_t>(svcntd());
            for (int k = 0; k < calls; ++k) {
                for (std::int64_t i = blk.lo; i < blk.hi; i += step) {
                    const svbool_t pg = svwhilelt_b64(i, blk.hi);
                    const svfloat64_t vb = svld1_f64(pg, b + i);
                    const svfloat64_t vc = Op::reads > 1 ? svld1_f64(pg, c + i) : vb;
                    svstnt1_f64(pg, a + i, Op::apply_sve(pg, vb, vc));
                }
                compiler_fence();
            }
            nt_fence();
        }
    }
#endif

    // Each thread copies its own block with one rep movsb a call (only copy has this variant:
    // the string instructions move or fill, they do not compute).
    __attribute__((noinline)) static void rep_copy_loop(double* a, const double* b, std::int64_t n, int calls) {
#pragma omp parallel
        {
            const Block blk = my_line_block(n);
            const std::size_t bytes =
                static_cast<std::size_t>(blk.hi - blk.lo) * sizeof(double);  // line_block: hi >= lo
            for (int k = 0; k < calls; ++k) {
                rep_movsb(a + blk.lo, b + blk.lo, bytes);
                compiler_fence();
            }
            nt_fence();
        }
    }

    KernelConfig cfg_;
    Pattern pattern_ = Pattern::sequential;
    std::int64_t stride_ = 0;
    std::uint64_t n_ = 0;
    double* a_ = nullptr;
    double* b_ = nullptr;
    double* c_ = nullptr;
    std::uint32_t* p_ = nullptr;
};

// The registry entry every stream kernel shares: element unit, the three patterns, bytes.
// The caller adds make and validate.
inline KernelEntry stream_entry(const char* name, const char* formula, bool has_nt, bool has_rep, double read_bytes,
                                double write_bytes, double flops, const char* notes) {
    KernelEntry e;
    e.info.name = name;
    e.info.group = "stream";
    e.info.formula = formula;
    e.info.unit = "element";
    e.info.axis = AccessAxis::pattern;
    e.info.accesses = {"sequential", "random", "strided"};
    e.info.variants = {""};
    if (has_nt) e.info.variants.push_back("nt");
    if (has_rep && have_string_ops) e.info.variants.push_back("rep");
    e.info.size_kind = SizeKind::bytes;
    e.info.metric = Metric::bandwidth;
    e.info.read_bytes_per_unit = read_bytes;
    e.info.write_bytes_per_unit = write_bytes;
    e.info.flops_per_unit = flops;
    e.info.notes = notes;
    return e;
}

template <class Op>
bool register_stream_kernel() {
    KernelEntry e =
        stream_entry(Op::name, Op::formula, Op::has_nt, Op::has_rep, 8.0 * Op::reads, 8.0, Op::flops, Op::notes);
    e.make = [](const KernelConfig& cfg) { return std::make_unique<StreamKernel<Op>>(cfg); };
    e.validate = [](const KernelConfig& cfg) { validate_stream_config(cfg, Op::name, StreamKernel<Op>::arrays()); };
    return register_kernel(std::move(e));
}

}  // namespace suite::stream
