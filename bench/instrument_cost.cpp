// How long the instruments take around one repetition: counters (the default events on every
// thread of a team) and energy (every domain of a sysfs tree) started and stopped N times with
// nothing between, so the figure is their own cost per repetition. Divided by the time of one
// repetition of a kernel, it bounds how much they can change the measured bandwidth (they are
// read outside the timed interval, so this is the worst case, not the expected effect).
//   usage: suite-instrument-cost [THREADS] [SYSFS_ROOT] [N]
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "harness/measure/instrument_set.hpp"
#include "rapl/energy.hpp"

int main(int argc, char** argv) {
    using namespace suite;
    const int threads = argc > 1 ? std::atoi(argv[1]) : 2;
    const std::string root = argc > 2 ? argv[2] : sysfs_root();
    const int n = argc > 3 ? std::atoi(argv[3]) : 20000;
    Instruments in = make_instruments("default", "none", {});
    in.energy = std::make_shared<EnergyMeter>(EnergyMeter::open(EnergyBackend::sysfs, root));
    TeamCounters counters(in.counters.events, threads, in.access);
    EnergyInstrument* energy = in.energy->available() ? in.energy.get() : nullptr;
    auto time_it = [&](bool with_counters, bool with_energy) {
        const auto t0 = std::chrono::steady_clock::now();
        for (int i = 0; i < n; ++i) {
            if (with_energy) energy->start();
            if (with_counters) counters.start();
            if (with_counters) counters.stop();
            if (with_energy) energy->stop(1e-3);
        }
        const double us = std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - t0).count() / n;
        if (with_energy) (void)energy->take(1, 1, 1, 1e-3);
        return us;
    };
    std::printf("events: %zu on %d thread(s); energy domains: %zu (%s)\n", in.counters.events.size(), threads,
                in.energy->domains().size(), energy ? root.c_str() : in.energy->reason().c_str());
    std::printf("counters: %.2f us per repetition\n", time_it(true, false));
    if (energy) std::printf("energy:   %.2f us per repetition\n", time_it(false, true));
    if (energy) std::printf("both:     %.2f us per repetition\n", time_it(true, true));
    return 0;
}
