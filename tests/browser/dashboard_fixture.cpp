// The browser test's page: writes the synthetic history of tests/results/synthetic_series.hpp
// (or an empty one) with write_dashboard and Debian's Chart.js, as `suite history html` would.
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
        const auto history = empty ? std::vector<suite::Series>{} : suite::test::synthetic_history();
        std::printf("%s\n", suite::write_dashboard(history, argv[1], options).c_str());
        return 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "dashboard_fixture: %s\n", e.what());
        return 2;
    }
}
