// The interface carries application kernels too: sized by a count, laid out in an ordering.
// This test-only kernel gathers y[i] = x[order[i]] over `count` items; it goes through the same
// registry and runner as the streaming kernels (and so through the registry walk as well).
#include <gtest/gtest.h>

#include <numeric>

#include "harness/measure/runner.hpp"

using namespace suite;

namespace {

class Gather final : public Kernel {
public:
    explicit Gather(const KernelConfig& cfg) : cfg_(cfg) {}
    void setup(Arena& arena) override {
        n_ = cfg_.size;
        x_ = arena.allocate<double>("x", n_);
        y_ = arena.allocate<double>("y", n_);
        order_ = arena.allocate<std::uint64_t>("order", n_);
        for (std::uint64_t i = 0; i < n_; ++i) {
            x_[i] = static_cast<double>(i);
            y_[i] = -1;
            // "random": a fixed odd-multiplier permutation of a power-of-two count.
            order_[i] = cfg_.access.name == "natural" ? i : (i * 2654435761u) % n_;
        }
    }
    void run(int calls) override {
        for (int c = 0; c < calls; ++c) {
#pragma omp parallel for schedule(static)
            for (std::int64_t i = 0; i < static_cast<std::int64_t>(n_); ++i) y_[i] = x_[order_[i]];
        }
    }
    Verification verify() override {
        Verification v{true, "y[i] == order[i]", 0};
        for (std::uint64_t i = 0; i < n_; ++i)
            if (y_[i] != static_cast<double>(order_[i])) v.passed = false;
        return v;
    }
    Work work() const override { return {static_cast<double>(n_), 24.0 * n_, 24.0 * n_, 0, n_ * 24}; }

private:
    KernelConfig cfg_;
    std::uint64_t n_ = 0;
    double *x_ = nullptr, *y_ = nullptr;
    std::uint64_t* order_ = nullptr;
};

const bool registered = [] {
    KernelEntry e;
    e.info.name = "test-gather";
    e.info.group = "test";
    e.info.formula = "y[i] = x[order[i]]";
    e.info.unit = "item";
    e.info.axis = AccessAxis::ordering;
    e.info.accesses = {"natural", "random"};
    e.info.size_kind = SizeKind::count;
    e.make = [](const KernelConfig& c) { return std::make_unique<Gather>(c); };
    e.test_size = 1024;
    return register_kernel(std::move(e));
}();

}  // namespace

TEST(AppKernelInterface, CountSizedOrderingKernelRunsThroughTheRunner) {
    const Topology topo = Topology::load();
    RunSettings s;
    s.pin = parse_pin("compact", topo);
    s.placement = parse_placement("local", topo);
    s.reps = 3;
    for (const char* ordering : {"natural", "random"}) {
        Record r = run_point({find_kernel("test-gather"), {ordering, 0}, "", 4096, 1}, s, topo);
        EXPECT_TRUE(r.verification.passed);
        EXPECT_EQ(r.axis, AccessAxis::ordering);
        EXPECT_EQ(r.access, ordering);
        EXPECT_EQ(r.size_kind, SizeKind::count);
        EXPECT_EQ(r.size_requested, 4096u);
        EXPECT_EQ(r.work.units, 4096.0);
        EXPECT_EQ(r.pages.size(), 3u);
        ASSERT_TRUE(r.rates.stream_gbps_best.has_value());
        EXPECT_NEAR(*r.rates.stream_gbps_best, 24.0 * 4096 / r.time.min / 1e9, 1e-9);
    }
}
