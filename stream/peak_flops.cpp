// peak-flops:       for (i = 0; i < n; ++i) for (k = 0; k < 12; ++k) x[k] = fma(x[k], m, a);
// The ceiling of the roofline: double-precision fused multiply-adds on values held in
// registers, no memory traffic at all. Twelve independent accumulators per thread hide the
// FMA's latency (4 cycles on current x86 cores with two FMA pipes need 8 in flight).
// One variant per instruction width the build targets, chosen with --isa:
//   x86-64   scalar  vfmadd231sd   1 double per instruction
//            sse     vfmadd231pd   2 (xmm)
//            avx     vfmadd231pd   4 (ymm)       where the build targets AVX
//            avx512  vfmadd231pd   8 (zmm)       where the build targets AVX-512F
//   aarch64  scalar  fmadd d       1
//            neon    fmla v.2d     2
//            sve     fmla/fmad z.d the CPU's vector length (2 to 32), where the CPU has SVE:
//                                  compiled for SVE in any aarch64 build, chosen at run time
// Without FMA in the ISA (a build for plain x86-64) each update is a multiply and an add:
// still 2 flops, counted the same way. The size is a count: loop iterations per thread per
// call, so every thread does the same work whatever the thread count (a peak scales with the
// cores). Each update counts 2 flops per lane; bytes: none.
//
// Check: m is 1 and a is 2^-20, read at run time through an empty asm that the compiler cannot
// see through, so it can neither fold the loop nor drop it. Every lane starts at a distinct
// small multiple of 2^-20 and gains exactly a per update: after N updates it must equal
// start + N a bit for bit (all values stay far below 2^33, where the sums are exact). The FMA
// itself takes the same time whatever its operands (no denormals occur).
// tests/cli/e2e_test.cpp checks in the binary that each variant's loop is the intended
// instructions and nothing else (it caught GCC packing 8 of the 12 scalar chains into two ymm
// FMAs, which made "scalar" 2.7x faster than scalar).
#include <omp.h>
#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#elif defined(__aarch64__)
#include <arm_neon.h>
#endif

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "harness/common/choice_table.hpp"
#include "harness/common/units.hpp"
#include "harness/kernel/kernel.hpp"
#include "stream/arch.hpp"

namespace suite::stream {
namespace {

constexpr int accumulators = 12;
#if defined(__aarch64__)
constexpr int max_lanes = 32;  // SVE's longest vector, 2048 bits
#define SUITE_VREG "+w"        // an FP/SIMD (or SVE) register
#else
constexpr int max_lanes = 8;  // AVX-512
#define SUITE_VREG "+v"
#endif
constexpr double step = 1.0 / (1 << 20);  // a, exactly representable

// One instruction width: its register type, how many doubles it holds, the update.
struct Scalar {
    using V = double;
    static constexpr int lanes = 1;
    static V set(double v) { return v; }
#if defined(__FMA__) || defined(__ARM_FEATURE_FMA)
    static V fma(V x, V m, V a) { return __builtin_fma(x, m, a); }
#else
    static V fma(V x, V m, V a) { return x * m + a; }
#endif
    static void store(double* p, V v) { *p = v; }
    static V load(const double* p) { return *p; }
};

#if defined(__x86_64__) || defined(__i386__)
struct Sse {
    using V = __m128d;
    static constexpr int lanes = 2;
    static V set(double v) { return _mm_set1_pd(v); }
#ifdef __FMA__
    static V fma(V x, V m, V a) { return _mm_fmadd_pd(x, m, a); }
#else
    static V fma(V x, V m, V a) { return _mm_add_pd(_mm_mul_pd(x, m), a); }
#endif
    static void store(double* p, V v) { _mm_storeu_pd(p, v); }
    static V load(const double* p) { return _mm_loadu_pd(p); }
};

#ifdef __AVX__
struct Avx {
    using V = __m256d;
    static constexpr int lanes = 4;
    static V set(double v) { return _mm256_set1_pd(v); }
#ifdef __FMA__
    static V fma(V x, V m, V a) { return _mm256_fmadd_pd(x, m, a); }
#else
    static V fma(V x, V m, V a) { return _mm256_add_pd(_mm256_mul_pd(x, m), a); }
#endif
    static void store(double* p, V v) { _mm256_storeu_pd(p, v); }
    static V load(const double* p) { return _mm256_loadu_pd(p); }
};
#endif

#ifdef __AVX512F__
struct Avx512 {
    using V = __m512d;
    static constexpr int lanes = 8;
    static V set(double v) { return _mm512_set1_pd(v); }
    static V fma(V x, V m, V a) { return _mm512_fmadd_pd(x, m, a); }
    static void store(double* p, V v) { _mm512_storeu_pd(p, v); }
    static V load(const double* p) { return _mm512_loadu_pd(p); }
};
#endif
#endif  // x86

#if defined(__aarch64__)
struct Neon {
    using V = float64x2_t;
    static constexpr int lanes = 2;
    static V set(double v) { return vdupq_n_f64(v); }
    // x + m * a: FMLA accumulates into its first operand, so the chain is x (a + x * m would
    // need a copy of a before every FMLA); with m = 1 both are x + a.
    static V fma(V x, V m, V a) { return vfmaq_f64(x, m, a); }
    static void store(double* p, V v) { vst1q_f64(p, v); }
    static V load(const double* p) { return vld1q_f64(p); }
};
#endif

// The timed loop of one width: `n` iterations of 12 independent updates on registers. Kept
// out of line so that the objdump test finds it by name.
template <class W>
__attribute__((noinline)) void peak_loop(double* x, double m_in, double a_in, std::int64_t n) {
    using V = typename W::V;
    double m_s = m_in, a_s = a_in;
    asm volatile("" : SUITE_VREG(m_s), SUITE_VREG(a_s));  // opaque: neither 1 nor 2^-20 to the compiler
    const V m = W::set(m_s), a = W::set(a_s);
    V acc[accumulators];
#pragma GCC unroll 12
    for (int k = 0; k < accumulators; ++k) acc[k] = W::load(x + k * W::lanes);
    for (std::int64_t i = 0; i < n; ++i) {
#pragma GCC unroll 12
        for (int k = 0; k < accumulators; ++k) {
            acc[k] = W::fma(acc[k], m, a);
            // Each accumulator stays one register of its width: without this GCC packs
            // scalar (or 128-bit) chains into wider vectors, and "scalar" would not be.
            asm("" : SUITE_VREG(acc[k]));
        }
    }
#pragma GCC unroll 12
    for (int k = 0; k < accumulators; ++k) W::store(x + k * W::lanes, acc[k]);
}

#if SUITE_HAVE_SVE_TWINS
// The SVE loop: sizeless vectors cannot be array elements, so the twelve chains are named.
#define SUITE_SVE_CHAINS(X) X(0) X(1) X(2) X(3) X(4) X(5) X(6) X(7) X(8) X(9) X(10) X(11)
SUITE_SVE std::int64_t sve_doubles() { return static_cast<std::int64_t>(svcntd()); }
__attribute__((noinline)) SUITE_SVE void peak_loop_sve(double* x, double m_in, double a_in, std::int64_t n) {
    double m_s = m_in, a_s = a_in;
    asm volatile("" : SUITE_VREG(m_s), SUITE_VREG(a_s));
    const svbool_t all = svptrue_b64();
    const svfloat64_t m = svdup_n_f64(m_s), a = svdup_n_f64(a_s);
    const std::int64_t w = sve_doubles();
#define SUITE_SVE_LOAD(k) svfloat64_t acc##k = svld1_f64(all, x + (k)*w);
    SUITE_SVE_CHAINS(SUITE_SVE_LOAD)
    for (std::int64_t i = 0; i < n; ++i) {
#define SUITE_SVE_FMA(k)                     \
    acc##k = svmla_f64_x(all, a, acc##k, m); \
    asm("" : SUITE_VREG(acc##k));
        SUITE_SVE_CHAINS(SUITE_SVE_FMA)
    }
#define SUITE_SVE_STORE(k) svst1_f64(all, x + (k)*w, acc##k);
    SUITE_SVE_CHAINS(SUITE_SVE_STORE)
}
#endif

using Loop = void (*)(double*, double, double, std::int64_t);

// What an --isa choice runs: its lanes, its loop, the instruction's suffix the objdump test looks for.
struct Width {
    int lanes = 1;
    Loop loop = nullptr;
    const char* instruction = "";
};

// The widths this build has, narrowest first: --isa's choices, one table.
const ChoiceTable<Width>& isas() {
    static const ChoiceTable<Width> table{
        "instruction width",
        {
#if defined(__x86_64__) || defined(__i386__)
            {"scalar", "1 double per instruction", {Scalar::lanes, &peak_loop<Scalar>, "sd"}},
            {"sse", "2 doubles (xmm)", {Sse::lanes, &peak_loop<Sse>, "pd xmm"}},
#ifdef __AVX__
            {"avx", "4 doubles (ymm)", {Avx::lanes, &peak_loop<Avx>, "pd ymm"}},
#endif
#ifdef __AVX512F__
            {"avx512", "8 doubles (zmm)", {Avx512::lanes, &peak_loop<Avx512>, "pd zmm"}},
#endif
#elif defined(__aarch64__)
            {"scalar", "1 double per instruction (fmadd d)", {Scalar::lanes, &peak_loop<Scalar>, "fmadd\td"}},
            {"neon", "2 doubles (fmla v.2d)", {Neon::lanes, &peak_loop<Neon>, "fmla\tv"}},
            {"sve",
             "the CPU's SVE vector (fmla z.d), where the CPU has SVE",
             {cpu_has_sve() ? static_cast<int>(sve_doubles()) : 0, &peak_loop_sve, "z"}},
#endif
        }};
    return table;
}

// The widths this CPU runs: the build's, less SVE where the CPU has none.
std::vector<std::string> usable_isas() {
    std::vector<std::string> out = isas().names();
    if (!cpu_has_sve()) std::erase(out, std::string("sve"));
    return out;
}

using Isa = Width;
const Isa& isa_of(const std::string& variant) { return isas().at(variant).what; }

// Each thread's accumulators and its count of calls, on cache lines of their own.
struct alignas(64) ThreadState {
    double x[accumulators * max_lanes];
    std::uint64_t calls = 0;
};

// The value lane j of accumulator k of thread t starts from: distinct, small, a multiple of a.
double start_value(int t, int k, int j) { return static_cast<double>(1 + t * 97 + k * 8 + j) * step; }

class PeakFlops final : public Kernel {
public:
    explicit PeakFlops(const KernelConfig& cfg) : cfg_(cfg), isa_(isa_of(cfg.variant)) {}

    void setup(Arena&) override {
        state_.assign(static_cast<std::size_t>(cfg_.threads), ThreadState{});
        int team = 0;
#pragma omp parallel num_threads(cfg_.threads) reduction(max : team)
        {
            team = omp_get_num_threads();
            const int t = omp_get_thread_num();
            ThreadState& s = state_[static_cast<std::size_t>(t)];
            for (int k = 0; k < accumulators; ++k)
                for (int j = 0; j < isa_.lanes; ++j) s.x[k * isa_.lanes + j] = start_value(t, k, j);
        }
        require_team_size(team, cfg_.threads);
    }

    // Each thread works on its own registers: no call waits for another thread.
    void run(int calls) override {
        const Loop loop = isa_.loop;
        const auto n = static_cast<std::int64_t>(cfg_.size);
        ThreadState* states = state_.data();
#pragma omp parallel num_threads(cfg_.threads)
        {
            ThreadState& s = states[omp_get_thread_num()];
            for (int c = 0; c < calls; ++c) loop(s.x, 1.0, step, n);
            s.calls += static_cast<std::uint64_t>(calls);
        }
    }

    Verification verify() override {
        double worst = 0;
        std::string first;
        for (int t = 0; t < cfg_.threads; ++t) {
            const ThreadState& s = state_[static_cast<std::size_t>(t)];
            if (s.calls == 0) return {false, "thread " + std::to_string(t) + " made no call: nothing was computed", 0};
            const double updates = static_cast<double>(s.calls) * static_cast<double>(cfg_.size);
            for (int k = 0; k < accumulators; ++k)
                for (int j = 0; j < isa_.lanes; ++j) {
                    const double expect = start_value(t, k, j) + updates * step;
                    const double got = s.x[k * isa_.lanes + j];
                    if (got != expect && first.empty())
                        first = "thread " + std::to_string(t) + " accumulator " + std::to_string(k) + " lane " +
                                std::to_string(j) + ": " + format_number(got) + ", expected " + format_number(expect);
                    worst = std::max(worst, std::abs(got - expect));
                }
        }
        if (!first.empty()) return {false, first, worst};
        return {true,
                "every lane of the " + std::to_string(accumulators) +
                    " accumulators of each thread equals its start plus " + "calls x " + std::to_string(cfg_.size) +
                    " updates of 2^-20, exactly",
                0};
    }

    Work work() const override {
        Work w;
        const double updates = static_cast<double>(cfg_.size) * accumulators * isa_.lanes * cfg_.threads;
        w.units = updates;  // one lane's multiply-add
        w.flops = 2 * updates;
        w.footprint_bytes = static_cast<std::uint64_t>(cfg_.threads) * sizeof(ThreadState);
        return w;
    }

    std::vector<Fact> facts() const override {
        return {{"lanes", static_cast<double>(isa_.lanes), "doubles per instruction"},
                {"accumulators", static_cast<double>(accumulators), "independent chains per thread"}};
    }

private:
    KernelConfig cfg_;
    const Isa& isa_;
    std::vector<ThreadState> state_;
};

const bool registered = [] {
    KernelEntry e;
    e.info.name = "peak-flops";
    e.info.group = "compute";
    e.info.formula = "x[k] = fma(x[k], m, a), 12 independent k, in registers";
    e.info.unit = "fma-lane";
    e.info.axis = AccessAxis::pattern;
    e.info.accesses = {"registers"};
    e.info.variants = isas().names();  // no plain kernel: every width is named
    e.info.default_variants = usable_isas();
    e.info.variant_option = "isa";
    e.info.size_kind = SizeKind::count;
    e.info.default_count = 1 << 18;
    e.test_size = 1 << 12;
    e.info.metric = Metric::bandwidth;
    e.info.flops_per_unit = 2;
    e.info.notes =
        "the roofline's compute ceiling: size = iterations per thread per call, each 12 FMAs of one width; no memory "
        "traffic";
    e.make = [](const KernelConfig& cfg) { return std::make_unique<PeakFlops>(cfg); };
    e.validate = [](const KernelConfig& cfg) {
        if (isas().find("sve") && cfg.variant == "sve" && !cpu_has_sve())
            throw UsageError(
                "peak-flops --isa=sve: this CPU has no SVE (its HWCAP lacks it); this build and CPU have: " +
                join(usable_isas(), ", "));
        if (cfg.size < 1) throw UsageError("peak-flops needs a size of at least 1 (iterations per thread per call)");
        if (cfg.size > (1ULL << 32))
            throw UsageError("peak-flops: size " + std::to_string(cfg.size) +
                             " is above 2^32 iterations per call (the check's sums must stay exact)");
    };
    return register_kernel(std::move(e));
}();

}  // namespace
}  // namespace suite::stream
