// latency (pointer chase):   for (k = 0; k < steps; ++k) p = p->next;
// Each thread owns footprint/threads bytes of 64 B lines linked into one cycle; `random` links
// them in a uniformly random cyclic order (a Fisher-Yates shuffle of the lines, each linked to
// the next in shuffled order), so every load depends on the one before and no prefetcher can
// guess the next line; `sequential` links each line to the next, the prefetcher-friendly
// reference. One repetition takes one step more than the cycle has lines, so that each
// repetition ends somewhere else and verify() can tell how many steps were really taken. The
// headline is nanoseconds per load; with several threads it is the loaded latency each sees.
#include <omp.h>

#include <cmath>
#include <random>
#include <vector>

#include "harness/common/units.hpp"
#include "harness/kernel/kernel.hpp"
#include "harness/kernel/patterns.hpp"

namespace suite::stream {
namespace {

struct alignas(64) Line {
    Line* next;
    std::uint64_t order;  // scratch for building the cycle, so setup needs no extra memory
    char pad[64 - sizeof(Line*) - sizeof(std::uint64_t)];
};
static_assert(sizeof(Line) == 64);

class Latency final : public Kernel {
public:
    explicit Latency(const KernelConfig& cfg) : cfg_(cfg) {}

    static std::uint64_t lines_per_thread(const KernelConfig& cfg) {
        return cfg.size / sizeof(Line) / static_cast<std::uint64_t>(cfg.threads);
    }

    void setup(Arena& arena) override {
        const int nt = cfg_.threads;
        per_thread_ = lines_per_thread(cfg_);
        lines_ = per_thread_ * static_cast<std::uint64_t>(nt);
        mem_ = arena.allocate<Line>("lines", lines_);
        pos_.assign(static_cast<std::size_t>(nt), nullptr);
        start_.assign(static_cast<std::size_t>(nt), nullptr);
        const bool random = pattern_of(cfg_.access) == Pattern::random;
        int team = 0;
#pragma omp parallel num_threads(nt) reduction(max : team)
        {
            team = omp_get_num_threads();
            // Each thread links (and so first-touches) its own region.
            const int t = omp_get_thread_num();
            Line* base = mem_ + per_thread_ * static_cast<std::uint64_t>(t);
            const std::uint64_t L = per_thread_;
            for (std::uint64_t k = 0; k < L; ++k) base[k].order = k;
            if (random) {
                std::mt19937_64 rng(cfg_.seed * 1000003u + static_cast<std::uint64_t>(t));
                for (std::uint64_t i = L - 1; i > 0; --i) {
                    const auto j = static_cast<std::uint64_t>((static_cast<unsigned __int128>(rng()) * (i + 1)) >> 64);
                    std::swap(base[i].order, base[j].order);
                }
            }
            // base[k].order is the k-th line of the walk: link each to the one after it.
            for (std::uint64_t k = 0; k < L; ++k) base[base[k].order].next = &base[base[(k + 1) % L].order];
            start_[t] = pos_[t] = &base[base[0].order];
        }
        require_team_size(team, nt);
    }

    void run(int calls) override {
        const std::uint64_t steps = per_thread_ + 1;
#pragma omp parallel num_threads(cfg_.threads)
        {
            const int t = omp_get_thread_num();
            Line* p = pos_[t];
            for (int c = 0; c < calls; ++c)
                for (std::uint64_t k = 0; k < steps; ++k) p = p->next;
            pos_[t] = p;  // stored, so the chase cannot be optimised away
        }
        calls_ += static_cast<std::uint64_t>(calls);
    }

    Verification verify() override {
        if (calls_ == 0) return {false, "the chase never ran", 0};
        // After `calls_` repetitions of L+1 steps on a cycle of L lines, each thread stands
        // calls_ mod L lines after its start; and the cycle has exactly L lines. The cycles are
        // walked in parallel, one per thread, as long as a repetition.
        const std::uint64_t offset = calls_ % per_thread_;
        const int nt = static_cast<int>(pos_.size());
        std::vector<std::string> problems(static_cast<std::size_t>(nt));
#pragma omp parallel for num_threads(nt) schedule(static, 1)
        for (int t = 0; t < nt; ++t) {
            const Line* p = start_[t];
            std::uint64_t length = 0;
            const Line* expect = nullptr;
            do {
                if (length == offset) expect = p;
                p = p->next;
                ++length;
            } while (p != start_[t] && length <= per_thread_);
            if (length != per_thread_)
                problems[t] = "thread " + std::to_string(t) + "'s chain has a cycle of " + std::to_string(length) +
                              " lines, not " + std::to_string(per_thread_);
            else if (pos_[t] != expect)
                problems[t] = "thread " + std::to_string(t) + " does not stand where " + std::to_string(calls_) +
                              " repetitions of the chase lead";
        }
        for (const auto& problem : problems)
            if (!problem.empty()) return {false, problem, 0};
        return {true,
                "each thread's chain is one cycle over its " + std::to_string(per_thread_) + " lines and, after " +
                    std::to_string(calls_) + " repetitions, stands where that many steps lead",
                0};
    }

    Work work() const override {
        Work w;
        const double loads = static_cast<double>((per_thread_ + 1) * static_cast<std::uint64_t>(cfg_.threads));
        w.units = loads;  // all threads together
        w.stream_bytes = loads * sizeof(Line*);
        w.hardware_bytes = loads * sizeof(Line);
        w.footprint_bytes = lines_ * sizeof(Line);
        return w;
    }

private:
    KernelConfig cfg_;
    std::uint64_t lines_ = 0, per_thread_ = 0, calls_ = 0;
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
    e.info.accesses = {pattern_name(Pattern::random), pattern_name(Pattern::sequential)};
    e.info.size_kind = SizeKind::bytes;
    e.info.metric = Metric::latency;
    e.info.read_bytes_per_unit = 8;
    e.info.notes = "ns per dependent load; each thread chases its own cycle over footprint/threads";
    e.make = [](const KernelConfig& cfg) { return std::make_unique<Latency>(cfg); };
    e.validate = [](const KernelConfig& cfg) {
        if (Latency::lines_per_thread(cfg) < 2)
            throw UsageError("size " + format_bytes(cfg.size) + " is too small for latency with " +
                             std::to_string(cfg.threads) +
                             " thread(s): each thread needs at least 2 cache lines; use at least " +
                             format_bytes(2 * sizeof(Line) * static_cast<std::uint64_t>(cfg.threads)));
    };
    return register_kernel(std::move(e));
}();

}  // namespace
}  // namespace suite::stream
