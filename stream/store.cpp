// store (write-only): for (i = 0; i < n; ++i) a[i] = v;      v = 1 + (call number mod 4096)
// 8 B per element by the STREAM convention (nothing read, 8 written), no flops. The counterpart
// of likwid-bench's store kernels: the writing half of the memory system alone. A plain store to
// a line that is not in cache first reads it (write-allocate), so the hardware moves 16 B per
// element; the nt variant streams the stores past the caches and moves 8 B; the rep variant fills
// each thread's block with one rep stosq, the instruction of glibc's memset.
// Each call stores a value of its own, so verify() can tell that the latest call wrote every
// element (not merely that some call did). Patterns as the other stream kernels.
#include <bit>

#include "stream/stream_kernel.hpp"

namespace suite::stream {
namespace {

// The value call number `call` (counted from 0 over the kernel's life) stores: never init_a.
inline double stored_value(std::uint64_t call) { return 1.0 + static_cast<double>(call % 4096); }

class Store final : public Kernel {
public:
    explicit Store(const KernelConfig& cfg) : cfg_(cfg) {}

    void setup(Arena& arena) override {
        pattern_ = pattern_of(cfg_.access);
        stride_ = static_cast<std::int64_t>(cfg_.access.stride);
        n_ = stream_elements(cfg_, 1);
        a_ = arena.allocate<double>("a", n_);
        if (pattern_ == Pattern::random) p_ = arena.allocate<std::uint32_t>("index", n_);
        double* __restrict a = a_;
        first_touch(cfg_, n_, p_, [&](std::int64_t i) { a[i] = init_a; });
    }

    // Sequential, strided and nt store only into the thread's own block: no barrier between
    // calls. Random stores anywhere, and a later call must not be overtaken by an earlier one's
    // stores from another thread, so its calls end at a barrier.
    void run(int calls) override {
        double* __restrict a = a_;
        const std::uint32_t* __restrict p = p_;
        const std::int64_t n = static_cast<std::int64_t>(n_), s = stride_;
        const int nt = cfg_.threads;
        if (cfg_.variant == "nt")
#if SUITE_HAVE_SVE_TWINS
            if (cpu_has_sve())
                nt_store_loop_sve(a, n, nt, calls_, calls);
            else
#endif
                nt_store_loop(a, n, nt, calls_, calls);
        else if (cfg_.variant == "rep")
            rep_store_loop(a, n, nt, calls_, calls);
        else
            switch (pattern_) {
                case Pattern::sequential:
                    sequential_loop(a, n, nt, calls_, calls);
                    break;
                case Pattern::random:
                    random_loop(a, p, n, nt, calls_, calls);
                    break;
                case Pattern::strided:
                    strided_loop(a, n, s, nt, calls_, calls);
                    break;
            }
        calls_ += static_cast<std::uint64_t>(calls);
    }

    Verification verify() override {
        Verification v;
        if (calls_ == 0) {
            v.detail = "the kernel never ran";
            return v;
        }
        const double expect = stored_value(calls_ - 1);
        const std::int64_t n = static_cast<std::int64_t>(n_);
        std::int64_t first_bad = n;
        double max_err = 0;
#pragma omp parallel for schedule(static) reduction(min : first_bad) reduction(max : max_err)
        for (std::int64_t i = 0; i < n; ++i)
            if (a_[i] != expect) {
                first_bad = std::min(first_bad, i);
                max_err = std::max(max_err, std::fabs(a_[i] - expect));
            }
        v.max_error = max_err;
        v.passed = first_bad == n;
        v.detail = "every a[i] holds the value of the latest of " + std::to_string(calls_) + " calls";
        if (!v.passed)
            v.detail += "; first mismatch at i=" + std::to_string(first_bad) + ": got " +
                        std::to_string(a_[first_bad]) + ", expected " + std::to_string(expect);
        return v;
    }

    Work work() const override { return stream_work(cfg_, n_, 0, 1, 0.0); }

private:
    // Unrolled by hand like the other sequential loops (see stream_kernel.hpp).
    __attribute__((noinline)) static void sequential_loop(double* __restrict a, std::int64_t n, int nt,
                                                          std::uint64_t first_call, int calls) {
#pragma omp parallel num_threads(nt)
        {
            const Block blk = my_line_block(n);
            for (int k = 0; k < calls; ++k) {
                const double v = stored_value(first_call + static_cast<std::uint64_t>(k));
                std::int64_t i = blk.lo;
                for (; i + unroll_elements <= blk.hi; i += unroll_elements) {
#pragma omp simd
                    for (std::int64_t j = i; j < i + unroll_elements; ++j) a[j] = v;
                }
                for (; i < blk.hi; ++i) a[i] = v;
                compiler_fence();
            }
        }
    }
    static void random_loop(double* __restrict a, const std::uint32_t* __restrict p, std::int64_t n, int nt,
                            std::uint64_t first_call, int calls) {
#pragma omp parallel num_threads(nt)
        {
            const Block blk = my_line_block(n);
            for (int k = 0; k < calls; ++k) {
                const double v = stored_value(first_call + static_cast<std::uint64_t>(k));
                for (std::int64_t i = blk.lo; i < blk.hi; ++i) a[p[i]] = v;
                barrier_between_calls();
            }
        }
    }
    static void strided_loop(double* __restrict a, std::int64_t n, std::int64_t s, int nt, std::uint64_t first_call,
                             int calls) {
#pragma omp parallel num_threads(nt)
        {
            const Block blk = my_line_block(n);
            for (int k = 0; k < calls; ++k) {
                const double v = stored_value(first_call + static_cast<std::uint64_t>(k));
                for (std::int64_t r = 0; r < s; ++r)
                    for (std::int64_t j = blk.lo + r; j < blk.hi; j += s) a[j] = v;
                compiler_fence();
            }
        }
    }
    // Streaming stores of a broadcast value from a vector boundary on, four vectors a step;
    // each thread fences its own stores once, after its last call (see StreamKernel's nt loop).
    __attribute__((noinline)) static void nt_store_loop(double* __restrict a, std::int64_t n, int nt,
                                                        std::uint64_t first_call, int calls) {
#pragma omp parallel num_threads(nt)
        {
            const Block blk = my_line_block(n);
            for (int k = 0; k < calls; ++k) {
                const double v = stored_value(first_call + static_cast<std::uint64_t>(k));
                ntvec vv;
                for (std::int64_t l = 0; l < nt_width; ++l) vv[l] = v;
                std::int64_t i = blk.lo;
                for (; i < blk.hi && (reinterpret_cast<std::uintptr_t>(a + i) % sizeof(ntvec)) != 0; ++i) a[i] = v;
                for (; i + 4 * nt_width <= blk.hi; i += 4 * nt_width) {
                    nt_store_pair(a + i, vv, vv);
                    nt_store_pair(a + i + 2 * nt_width, vv, vv);
                }
                for (; i + nt_width <= blk.hi; i += nt_width) nt_store(a + i, vv);
                for (; i < blk.hi; ++i) a[i] = v;
                compiler_fence();
            }
            nt_fence();
        }
    }

#if SUITE_HAVE_SVE_TWINS
    // The SVE twin of the nt loop: each vector streamed with STNT1D, vector-length agnostic.
    __attribute__((noinline)) SUITE_SVE static void nt_store_loop_sve(double* __restrict a, std::int64_t n, int nt,
                                                                      std::uint64_t first_call, int calls) {
#pragma omp parallel num_threads(nt)
        {
            const Block blk = my_line_block(n);
            const std::int64_t step = static_cast<std::int64_t>(svcntd());
            for (int k = 0; k < calls; ++k) {
                const svfloat64_t vv = svdup_n_f64(stored_value(first_call + static_cast<std::uint64_t>(k)));
                for (std::int64_t i = blk.lo; i < blk.hi; i += step) svstnt1_f64(svwhilelt_b64(i, blk.hi), a + i, vv);
                compiler_fence();
            }
            nt_fence();
        }
    }
#endif

    // Each thread fills its own block with one rep stosq a call: memset's instruction (it uses rep
    // stosb, for a byte; the stored double needs eight).
    __attribute__((noinline)) static void rep_store_loop(double* a, std::int64_t n, int nt, std::uint64_t first_call,
                                                         int calls) {
#pragma omp parallel num_threads(nt)
        {
            const Block blk = my_line_block(n);
            const std::size_t words = static_cast<std::size_t>(blk.hi - blk.lo);  // line_block: hi >= lo
            for (int k = 0; k < calls; ++k) {
                rep_stosq(a + blk.lo,
                          std::bit_cast<std::uint64_t>(stored_value(first_call + static_cast<std::uint64_t>(k))),
                          words);
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
    std::uint32_t* p_ = nullptr;
    std::uint64_t calls_ = 0;
};

const bool registered = [] {
    KernelEntry e = stream_entry("store", "a[i] = v", true, true, 0, 8, 0,
                                 "write-only: one stream of stores of a value that changes every call");
    e.make = [](const KernelConfig& cfg) { return std::make_unique<Store>(cfg); };
    e.validate = [](const KernelConfig& cfg) { validate_stream_config(cfg, "store", 1); };
    return register_kernel(std::move(e));
}();

}  // namespace
}  // namespace suite::stream
