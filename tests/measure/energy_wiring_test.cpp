// Energy as the engine sees it: an interface the program wires in (harness/instruments/energy.hpp).
// Without an opener nothing is measured and the reason says so; the opener's own refusal is a
// usage error of make_plan; and the runner starts and stops the instrument around every counted
// repetition, at the clock's points, then takes the point's readings once, with the point's batch.
#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <vector>

#include "harness/common/units.hpp"
#include "harness/instruments/energy.hpp"
#include "harness/machine/topology.hpp"
#include "harness/measure/instrument_set.hpp"
#include "harness/measure/plan.hpp"
#include "harness/measure/runner.hpp"

using namespace suite;

namespace {

// Counts what the runner does with it; reports one domain of 2 J a call.
class CountingEnergy final : public EnergyInstrument {
public:
    int starts = 0, stops = 0, takes = 0, open = 0;  // open: started and not yet stopped
    std::vector<double> stop_seconds;
    int take_batch = 0;
    double take_median = 0;
    bool requested() const override { return true; }
    bool available() const override { return true; }
    const std::string& reason() const override { return none_; }
    const std::string& backend() const override { return backend_; }
    std::vector<EnergyDomainInfo> domains() const override { return {{"package", 0, "counting", ""}}; }
    void start() override {
        ++starts;
        if (open++ != 0) ADD_FAILURE() << "started twice without a stop";
    }
    void stop(double seconds) override {
        ++stops;
        if (--open != 0) ADD_FAILURE() << "stopped without a start";
        stop_seconds.push_back(seconds);
    }
    EnergyReadings take(int batch, double, double, double median) override {
        ++takes;
        take_batch = batch;
        take_median = median;
        EnergyReadings r;
        r.requested = r.available = true;
        r.backend = backend_;
        DomainEnergy d;
        d.domain = "package";
        d.socket = 0;
        d.available = true;
        d.joules_per_call = {2, 2, 2};
        r.domains.push_back(d);
        return r;
    }
    void measure_idle(double) override {}

private:
    std::string none_, backend_ = "counting";
};

RunOptions copy_point() {
    RunOptions o;
    o.kernels = "copy";
    o.size = "64KiB";
    o.threads = "1";
    o.reps = 4;
    o.counters = "none";
    return o;
}

}  // namespace

TEST(EnergyWiring, WithoutAnOpenerNothingIsMeasuredAndTheReasonSaysWhy) {
    const Instruments automatic = make_instruments("none", "auto", {});
    EXPECT_TRUE(automatic.energy->requested());
    EXPECT_FALSE(automatic.energy->available());
    EXPECT_NE(automatic.energy->reason().find("no energy instrument"), std::string::npos) << automatic.energy->reason();
    const EnergyReadings r = automatic.energy->take(1, 1, 1, 1);
    EXPECT_FALSE(r.available);
    EXPECT_TRUE(r.domains.empty()) << "not measured is not 0 J";
    const Instruments none = make_instruments("none", "none", {});
    EXPECT_FALSE(none.energy->requested());
    EXPECT_EQ(none.energy->take(1, 1, 1, 1).reason, "energy was not requested");
    try {
        make_instruments("none", "sysfs", {});
        FAIL() << "--energy=sysfs accepted by a program with no energy instrument";
    } catch (const UsageError& e) {
        EXPECT_NE(std::string(e.what()).find("--energy=sysfs: this program reads no energy; accepted: auto, none"),
                  std::string::npos)
            << e.what();
    }
}

TEST(EnergyWiring, TheOpenerGetsTheOptionAndItsRefusalIsAUsageError) {
    std::vector<std::string> asked;
    const EnergyOpener refuse = [&asked](const std::string& option) -> std::unique_ptr<EnergyInstrument> {
        asked.push_back(option);
        throw UsageError("--energy=" + option + ": not this one");
    };
    RunOptions o = copy_point();
    o.energy = "perf";
    EXPECT_THROW(make_plan(o, Topology::load(), refuse), UsageError);
    EXPECT_EQ(asked, std::vector<std::string>{"perf"});
    const EnergyOpener null_opener = [](const std::string&) { return std::unique_ptr<EnergyInstrument>(); };
    EXPECT_THROW(make_plan(o, Topology::load(), null_opener), std::logic_error)
        << "an opener must return an instrument";
}

TEST(EnergyWiring, TheRunnerBracketsEveryRepetitionAndTakesThePointOnce) {
    const Topology topo = Topology::load();
    CountingEnergy* meter = nullptr;
    const EnergyOpener open = [&meter](const std::string&) {
        auto m = std::make_unique<CountingEnergy>();
        meter = m.get();
        return std::unique_ptr<EnergyInstrument>(std::move(m));
    };
    Plan plan = make_plan(copy_point(), topo, open);
    ASSERT_NE(meter, nullptr);
    ASSERT_EQ(plan.points.size(), 1u);
    plan.settings.instruments = &plan.instruments;
    const Record rec = run_point(plan.points[0], plan.settings, topo);
    EXPECT_EQ(meter->starts, rec.repetitions) << "one bracket a counted repetition, none around the warm-up";
    EXPECT_EQ(meter->stops, rec.repetitions);
    ASSERT_EQ(meter->stop_seconds.size(), rec.samples_s.size());
    for (std::size_t i = 0; i < rec.samples_s.size(); ++i)
        EXPECT_DOUBLE_EQ(meter->stop_seconds[i], rec.samples_s[i] * rec.batch)
            << "stop gets the clock's interval of repetition " << i;
    EXPECT_EQ(meter->takes, 1);
    EXPECT_EQ(meter->take_batch, rec.batch);
    EXPECT_DOUBLE_EQ(meter->take_median, rec.time.median);
    ASSERT_EQ(rec.energy.domains.size(), 1u);
    EXPECT_EQ(rec.energy.backend, "counting");
    EXPECT_DOUBLE_EQ(rec.energy.domains[0].joules_per_call.median, 2);
}
