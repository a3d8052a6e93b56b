// libFuzzer target: the size, sweep, thread-list and CPU-list parsers of the command line.
// Every input must either parse or throw UsageError; anything else (another exception, a crash,
// a sanitizer report, a parse whose result breaks the parser's own promises) is a bug.
// SOURCES: harness/common/units.cpp
#include <cstddef>
#include <cstdint>
#include <cmath>
#include <cstdlib>
#include <string>

#include "harness/common/units.hpp"

namespace {

void check(bool ok) {
    if (!ok) std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string text(reinterpret_cast<const char*>(data), size);
    using suite::UsageError;
    try {
        const std::uint64_t b = suite::parse_bytes(text);
        check(b >= 1);
        // What format_bytes prints (3 significant digits) must parse back to within 0.5 %.
        const double back = static_cast<double>(suite::parse_bytes(suite::format_bytes(b)));
        check(std::abs(back - static_cast<double>(b)) <= 0.005 * static_cast<double>(b));
    } catch (const UsageError&) {
    }
    try {
        const auto sizes = suite::parse_size_list(text);
        check(!sizes.empty() && sizes.size() <= 1000);
        for (auto s : sizes) check(s >= 1);
    } catch (const UsageError&) {
    }
    try {
        const auto threads = suite::parse_thread_list(text, 64);
        check(!threads.empty());
        for (int t : threads) check(t >= 1 && t <= 64);
    } catch (const UsageError&) {
    }
    try {
        const auto cpus = suite::parse_cpu_list(text);
        for (int c : cpus) check(c >= 0);
    } catch (const UsageError&) {
    }
    (void)suite::split(text, ',');
    return 0;
}
