// load (read-only):  for (i = 0; i < n; ++i) s += b[i];
// 8 B per element by the STREAM convention (8 read, nothing written), 1 flop (the add that
// keeps the loads observable). The counterpart of likwid-bench's load kernels: the reading half
// of the memory system alone, with no store stream and so no write-allocate.
// Patterns as the other stream kernels: random sums b[p[i]], strided:S walks each thread's block
// S times with stride S. Each thread sums on over all the calls of a run (the accumulators stay
// in registers, and a compiler fence after every call makes each call load b again), and stores
// its total and its count of calls where verify() reads them: the total must be exactly calls
// times the sum of the thread's elements (every partial sum of the initial values is a multiple
// of 0.5 below 2^52, so neither the order of the additions nor their number changes it).
#include "stream/stream_kernel.hpp"

#include <cstring>
#include <vector>

namespace suite::stream {
namespace {

// One thread's result, on its own cache line so that the threads' stores do not share one.
struct alignas(64) ThreadSum {
    double total = 0;         // the sum over all the calls the thread made
    std::uint64_t calls = 0;  // how many calls the thread finished
};

class Load final : public Kernel {
public:
    explicit Load(const KernelConfig& cfg) : cfg_(cfg) {}

    void setup(Arena& arena) override {
        pattern_ = pattern_of(cfg_.access);
        stride_ = static_cast<std::int64_t>(cfg_.access.stride);
        n_ = stream_elements(cfg_, 1);
        b_ = arena.allocate<double>("b", n_);
        if (pattern_ == Pattern::random) p_ = arena.allocate<std::uint32_t>("index", n_);
        sums_.assign(static_cast<std::size_t>(cfg_.threads), ThreadSum{});
        double* __restrict b = b_;
        first_touch(cfg_, n_, p_, [&](std::int64_t i) { b[i] = init_b(static_cast<std::uint64_t>(i)); });
    }

    // No pattern writes shared data, so no call waits for another thread.
    void run(int calls) override {
        const double* __restrict b = b_;
        const std::uint32_t* __restrict p = p_;
        const std::int64_t n = static_cast<std::int64_t>(n_), s = stride_;
        ThreadSum* sums = sums_.data();
        const int nt = cfg_.threads;
        switch (pattern_) {
            case Pattern::sequential:
                sequential_loop(b, sums, n, nt, calls);
                break;
            case Pattern::random:
                random_loop(b, p, sums, n, nt, calls);
                break;
            case Pattern::strided:
                strided_loop(b, sums, n, s, nt, calls);
                break;
        }
        calls_ += static_cast<std::uint64_t>(calls);
    }

    Verification verify() override {
        const std::int64_t n = static_cast<std::int64_t>(n_);
        const int nt = cfg_.threads;
        std::vector<double> expected(static_cast<std::size_t>(nt), 0.0);
#pragma omp parallel for num_threads(nt) schedule(static, 1)
        for (int t = 0; t < nt; ++t) {
            const Block blk = line_block(n, t, nt);
            double sum = 0;
            for (std::int64_t i = blk.lo; i < blk.hi; ++i)
                sum += init_b(pattern_ == Pattern::random ? p_[i] : static_cast<std::uint64_t>(i));
            expected[static_cast<std::size_t>(t)] = sum;
        }
        Verification v;
        if (calls_ == 0) {
            v.detail = "the kernel never ran";
            return v;
        }
        for (int t = 0; t < nt; ++t) {
            const ThreadSum& got = sums_[static_cast<std::size_t>(t)];
            const double want = expected[static_cast<std::size_t>(t)] * static_cast<double>(calls_);
            v.max_error = std::max(v.max_error, std::fabs(got.total - want));
            std::string problem;
            if (got.calls != calls_)
                problem = "ran " + std::to_string(got.calls) + " of " + std::to_string(calls_) + " calls";
            else if (got.total != want)
                problem = "summed " + std::to_string(got.total) + " over its calls, expected " + std::to_string(want);
            if (!problem.empty()) {
                v.detail = "thread " + std::to_string(t) + " " + problem;
                return v;
            }
        }
        v.passed = true;
        v.detail = "each thread's sum of its elements of b over " + std::to_string(calls_) + " calls, exactly";
        return v;
    }

    Work work() const override { return stream_work(cfg_, n_, 1, 0, 1.0); }  // the add keeps the loads

private:
    // Adds a run's calls to the thread's slot.
    static void record(ThreadSum& slot, double sum, int calls) {
        slot.total += sum;
        slot.calls += static_cast<std::uint64_t>(calls);
    }

    // Eight vector accumulators of the build's widest vector (arch.hpp's ntvec: 8 doubles with
    // AVX-512, 4 with AVX2, 2 with SSE2 and NEON), so that the adds of consecutive vectors do
    // not wait for one another and the loop runs at the speed of the loads. A vector wider than
    // the registers is not: GCC splits it in halves through the stack, and 64-byte vectors on an
    // AVX2 build (a Zen 3) stored and reloaded every accumulator every add, 17.6 GB/s at 32 KiB
    // against likwid-bench's 107. The accumulators are named locals, not an array: the compiler
    // fence after every call then leaves them in registers, where an array (indexed by the tail
    // loop) was stored and reloaded every call, which with two threads at 32 KiB cost a fifth of
    // the bandwidth. The tail has a sum of its own.
    using acc_vec = double __attribute__((vector_size(sizeof(ntvec))));
    // Taken by reference, not returned (a vector returned by value has an ABI that depends on
    // the ISA, which GCC warns of); inlined, the code is the same.
    static void add_loaded(acc_vec& acc, const double* p) {
        acc_vec v;
        std::memcpy(&v, p, sizeof v);  // an unaligned vector load
        acc += v;
    }
    __attribute__((noinline)) static void sequential_loop(const double* __restrict b, ThreadSum* sums, std::int64_t n,
                                                          int nt, int calls) {
#pragma omp parallel num_threads(nt)
        {
            const Block blk = my_line_block(n);
            ThreadSum& slot = sums[omp_get_thread_num()];
            constexpr std::int64_t w = sizeof(acc_vec) / sizeof(double), lanes = 8 * w;
            acc_vec a0{}, a1{}, a2{}, a3{}, a4{}, a5{}, a6{}, a7{};
            double tail = 0;
            for (int k = 0; k < calls; ++k) {
                std::int64_t i = blk.lo;
                for (; i + lanes <= blk.hi; i += lanes) {
                    add_loaded(a0, b + i);
                    add_loaded(a1, b + i + w);
                    add_loaded(a2, b + i + 2 * w);
                    add_loaded(a3, b + i + 3 * w);
                    add_loaded(a4, b + i + 4 * w);
                    add_loaded(a5, b + i + 5 * w);
                    add_loaded(a6, b + i + 6 * w);
                    add_loaded(a7, b + i + 7 * w);
                }
                for (; i < blk.hi; ++i) tail += b[i];
                compiler_fence();
            }
            // Folded once a run (a tree, vector adds first), not once a call, where in L1 it
            // cost a tenth of the loads.
            const acc_vec all = ((a0 + a1) + (a2 + a3)) + ((a4 + a5) + (a6 + a7));
            double sum = tail;
            for (std::int64_t l = 0; l < w; ++l) sum += all[l];
            record(slot, sum, calls);
        }
    }
    static void random_loop(const double* __restrict b, const std::uint32_t* __restrict p, ThreadSum* sums,
                            std::int64_t n, int nt, int calls) {
#pragma omp parallel num_threads(nt)
        {
            const Block blk = my_line_block(n);
            ThreadSum& slot = sums[omp_get_thread_num()];
            double sum = 0;
            for (int k = 0; k < calls; ++k) {
                for (std::int64_t i = blk.lo; i < blk.hi; ++i) sum += b[p[i]];
                compiler_fence();
            }
            record(slot, sum, calls);
        }
    }
    static void strided_loop(const double* __restrict b, ThreadSum* sums, std::int64_t n, std::int64_t s, int nt,
                             int calls) {
#pragma omp parallel num_threads(nt)
        {
            const Block blk = my_line_block(n);
            ThreadSum& slot = sums[omp_get_thread_num()];
            double sum = 0;
            for (int k = 0; k < calls; ++k) {
                for (std::int64_t r = 0; r < s; ++r)
                    for (std::int64_t j = blk.lo + r; j < blk.hi; j += s) sum += b[j];
                compiler_fence();
            }
            record(slot, sum, calls);
        }
    }

    KernelConfig cfg_;
    Pattern pattern_ = Pattern::sequential;
    std::int64_t stride_ = 0;
    std::uint64_t n_ = 0;
    double* b_ = nullptr;
    std::uint32_t* p_ = nullptr;
    std::vector<ThreadSum> sums_;
    std::uint64_t calls_ = 0;
};

const bool registered = [] {
    KernelEntry e = stream_entry("load", "s += b[i]", false, false, 8, 0, 1,
                                 "read-only: one stream of loads, each thread's sum kept and checked");
    e.make = [](const KernelConfig& cfg) { return std::make_unique<Load>(cfg); };
    e.validate = [](const KernelConfig& cfg) { validate_stream_config(cfg, "load", 1); };
    return register_kernel(std::move(e));
}();

}  // namespace
}  // namespace suite::stream
