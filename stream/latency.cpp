// latency (pointer chase):   for (k = 0; k < L; ++k) p = p->next;
// Each thread owns footprint/threads bytes of 64 B lines linked into one cycle; `random` links
// them in a seeded random cyclic order (Sattolo's algorithm), so every load depends on the one
// before and no prefetcher can guess the next line; `sequential` links each line to the next,
// the prefetcher-friendly reference. One repetition walks the whole cycle once. The headline is
// nanoseconds per load; with several threads it is the loaded latency each thread sees.
#include <omp.h>

#include <cmath>
#include <random>
#include <vector>

#include "harness/kernel.hpp"
#include "harness/units.hpp"

namespace suite::stream {
namespace {

struct alignas(64) Line {
    Line* next;
    char pad[64 - sizeof(Line*)];
};
static_assert(sizeof(Line) == 64);

class Latency final : public Kernel {
public:
    explicit Latency(const KernelConfig& cfg) : cfg_(cfg) {}

    void setup(Arena& arena) override {
        lines_ = cfg_.size / sizeof(Line);
        const int nt = cfg_.threads;
        per_thread_ = lines_ / static_cast<std::uint64_t>(nt);
        if (per_thread_ < 2)
            throw UsageError("size " + format_bytes(cfg_.size) + " is too small for latency with " + std::to_string(nt) +
                             " threads: each thread needs at least 2 cache lines (128 B)");
        lines_ = per_thread_ * static_cast<std::uint64_t>(nt);
        mem_ = arena.allocate<Line>("lines", lines_);
        pos_.assign(static_cast<std::size_t>(nt), nullptr);
        start_.assign(static_cast<std::size_t>(nt), nullptr);
        const bool random = cfg_.access.name == "random";
#pragma omp parallel num_threads(nt)
        {
            // Each thread links (and so first-touches) its own region.
            const int t = omp_get_thread_num();
            Line* base = mem_ + per_thread_ * static_cast<std::uint64_t>(t);
            std::vector<std::uint64_t> order(per_thread_);
            for (std::uint64_t k = 0; k < per_thread_; ++k) order[k] = k;
            if (random) {
                std::mt19937_64 rng(cfg_.seed * 1000003u + static_cast<std::uint64_t>(t));
                // Sattolo: a uniformly random permutation that is a single cycle.
                for (std::uint64_t i = per_thread_ - 1; i > 0; --i) {
                    const auto j = static_cast<std::uint64_t>((static_cast<unsigned __int128>(rng()) * i) >> 64);
                    std::swap(order[i], order[j]);
                }
            }
            for (std::uint64_t k = 0; k < per_thread_; ++k) base[order[k]].next = &base[order[(k + 1) % per_thread_]];
            start_[t] = pos_[t] = &base[order[0]];
        }
    }

    void run() override {
        const std::uint64_t steps = per_thread_;
#pragma omp parallel num_threads(cfg_.threads)
        {
            const int t = omp_get_thread_num();
            Line* p = pos_[t];
            for (std::uint64_t k = 0; k < steps; ++k) p = p->next;
            pos_[t] = p;  // stored, so the chase cannot be optimised away
        }
    }

    Verification verify() override {
        Verification v;
        v.passed = true;
        v.detail = "each thread's chain is one cycle over its " + std::to_string(per_thread_) +
                   " lines and every repetition ended where it started";
        for (std::size_t t = 0; t < pos_.size() && v.passed; ++t) {
            if (pos_[t] != start_[t]) {
                v.passed = false;
                v.detail = "thread " + std::to_string(t) + " did not end a repetition at its start line";
                break;
            }
            std::uint64_t length = 0;
            const Line* p = start_[t];
            do {
                p = p->next;
                ++length;
            } while (p != start_[t] && length <= per_thread_);
            if (length != per_thread_) {
                v.passed = false;
                v.detail = "thread " + std::to_string(t) + "'s chain has a cycle of " + std::to_string(length) + " lines, not " +
                           std::to_string(per_thread_);
            }
        }
        return v;
    }

    Work work() const override {
        Work w;
        w.units = static_cast<double>(lines_);  // loads, all threads together
        w.stream_bytes = static_cast<double>(lines_) * sizeof(Line*);
        w.hardware_bytes = static_cast<double>(lines_) * sizeof(Line);
        w.footprint_bytes = lines_ * sizeof(Line);
        return w;
    }

private:
    KernelConfig cfg_;
    std::uint64_t lines_ = 0, per_thread_ = 0;
    Line* mem_ = nullptr;
    std::vector<Line*> pos_, start_;
};

const bool registered = [] {
    KernelEntry e;
    e.info.name = "latency";
    e.info.group = "latency";
    e.info.formula = "p = p->next";
    e.info.unit = "load";
    e.info.axis = AccessAxis::pattern;
    e.info.accesses = {"random", "sequential"};
    e.info.size_kind = SizeKind::bytes;
    e.info.metric = Metric::latency;
    e.info.read_bytes_per_unit = 8;
    e.info.notes = "ns per dependent load; each thread chases its own cycle over footprint/threads";
    e.make = [](const KernelConfig& cfg) { return std::make_unique<Latency>(cfg); };
    e.min_size_per_thread = 2 * sizeof(Line);  // a cycle needs two lines
    return register_kernel(std::move(e));
}();

}  // namespace
}  // namespace suite::stream
