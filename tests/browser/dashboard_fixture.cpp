// The browser test's page: writes the synthetic history of tests/results/synthetic_series.hpp
// (or an empty one) with write_dashboard and Debian's Chart.js, as `suite history html` would,
// with two more series on its first machine: one whose repetitions spread 120 % (median - noise
// is below 0, and the axis must not be), and a counter that is 0 in every run (listed, not charted).
// Usage: dashboard_fixture OUT_DIR [--empty]    exit 0, or 2 with one line on stderr
#include <cstdio>
#include <exception>
#include <string>

#include "harness/results/dashboard.hpp"
#include "tests/results/synthetic_series.hpp"

int main(int argc, char** argv) {
    const bool empty = argc == 3 && std::string(argv[2]) == "--empty";
    if (argc != 2 && !empty) {
        std::fprintf(stderr, "usage: dashboard_fixture OUT_DIR [--empty]\n");
        return 2;
    }
    try {
        suite::DashboardOptions options;
        options.title = empty ? "suite history (empty)" : "suite history (synthetic)";
        auto history = empty ? std::vector<suite::Series>{} : suite::test::synthetic_history();
        if (!empty) {
            using namespace suite::test;
            const suite::Series& a = history.front();
            suite::Series wide =
                synthetic_one(a.machine, a.fingerprint, synthetic_key("scale", "sequential", 64ULL << 20, 1),
                              "bandwidth", "GB/s", suite::Direction::higher_is_better, {20.0, 0.1, {}}, 600);
            for (auto& e : wide.entries) e.noise = 1.2;
            suite::Series zero = synthetic_one(a.machine, a.fingerprint, synthetic_key("add", "random", 64 << 10, 2),
                                               "counter major-faults", "per call", suite::Direction::lower_is_better,
                                               {1.0, 0.0, {}}, 700);
            for (auto& e : zero.entries) {
                e.median = 0;
                e.samples.clear();
            }
            history.push_back(wide);
            history.push_back(zero);
        }
        std::printf("%s\n", suite::write_dashboard(history, argv[1], options).c_str());
        return 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "dashboard_fixture: %s\n", e.what());
        return 2;
    }
}
