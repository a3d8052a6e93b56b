// --fresh-arrays: each counted repetition after the first runs on a kernel set up anew on a new
// arena (its arrays allocated and first-touched again), the old one freed first, and warmed by
// one uncounted batch; the record says so (JSON repetitions.fresh_arrays). A kernel of this test
// counts its set-ups and how many of its kind are alive; a real kernel (triad) verifies under it.
#include <gtest/gtest.h>

#include <memory>

#include "harness/machine/topology.hpp"
#include "harness/measure/plan.hpp"
#include "harness/measure/runner.hpp"
#include "harness/results/report.hpp"

using namespace suite;

namespace {

struct Census {
    int setups = 0, alive = 0, most_alive = 0, calls_of_last = 0;
};
Census census;

class CountingKernel final : public Kernel {
public:
    CountingKernel() { census.most_alive = std::max(census.most_alive, ++census.alive); }
    ~CountingKernel() override { --census.alive; }
    void setup(Arena& arena) override {
        ++census.setups;
        data_ = arena.allocate<double>("a", 512);
        for (int i = 0; i < 512; ++i) data_[i] = 1;
    }
    void run(int calls) override {
        for (int c = 0; c < calls; ++c)
            for (int i = 0; i < 512; ++i) data_[i] += 1;
        calls_ += calls;
        census.calls_of_last = calls_;
    }
    Verification verify() override { return {calls_ > 0 && data_[0] == 1 + calls_, "counted"}; }
    Work work() const override {
        Work w;
        w.units = 512;
        w.stream_bytes = 16 * 512;
        return w;
    }

private:
    double* data_ = nullptr;
    long calls_ = 0;
};

KernelEntry counting_entry() {
    KernelEntry e;
    e.info.name = "counting";
    e.info.unit = "element";
    e.make = [](const KernelConfig&) { return std::make_unique<CountingKernel>(); };
    return e;
}

// Four counted repetitions of the counting kernel, the census taken from zero.
Record run_counting(bool fresh) {
    const Topology topo = Topology::load();
    static const KernelEntry entry = counting_entry();
    RunSettings s;
    s.pin = parse_pin("compact", topo);
    s.placement = parse_placement("local", topo);
    s.reps = 4;
    s.fresh_arrays = fresh;
    census = {};
    return run_point(Point{&entry, {}, "", 4096, 1}, s, topo);
}

}  // namespace

TEST(FreshArrays, EachRepetitionAfterTheFirstOnANewSetUp) {
    const Record rec = run_counting(true);
    EXPECT_TRUE(rec.verification.passed);
    EXPECT_TRUE(rec.fresh_arrays);
    EXPECT_EQ(census.setups, 4);
    EXPECT_EQ(census.most_alive, 1) << "the old kernel and its arrays go before the new ones are set up";
    EXPECT_EQ(census.alive, 0);
    // The last set-up ran one warm batch and one counted batch before it was verified.
    EXPECT_EQ(census.calls_of_last, 2 * rec.batch);
    EXPECT_EQ(to_json(rec)["repetitions"]["fresh_arrays"], true);
}

TEST(FreshArrays, OneSetUpByDefault) {
    const Record rec = run_counting(false);
    EXPECT_TRUE(rec.verification.passed);
    EXPECT_FALSE(rec.fresh_arrays);
    EXPECT_EQ(census.setups, 1);
    EXPECT_EQ(census.calls_of_last, rec.warmup + 4 * rec.batch);
    EXPECT_EQ(to_json(rec)["repetitions"]["fresh_arrays"], false);
}

TEST(FreshArrays, TriadVerifiesOnFreshArrays) {
    RunOptions o;
    o.kernels = "triad";
    o.size = "256KiB";
    o.threads = "1";
    o.reps = 3;
    o.counters = "none";
    o.fresh_arrays = true;
    const Topology topo = Topology::load();
    const Plan plan = make_plan(o, topo, {});
    ASSERT_TRUE(plan.settings.fresh_arrays);
    const Record rec = run_point(plan.points.at(0), plan.settings, topo);
    EXPECT_TRUE(rec.verification.passed) << rec.verification.detail;
    EXPECT_EQ(rec.repetitions, 3);
    EXPECT_GE(rec.warmup, 1 + 2 * rec.batch);
}
