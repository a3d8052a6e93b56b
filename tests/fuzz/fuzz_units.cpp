// libFuzzer target: the size, sweep, count, thread-list, CPU-list, whole-number and name-list
// parsers of the command line.
// Every input must either parse or throw UsageError; anything else (another exception, a crash,
// a sanitizer report, a parse whose result breaks the parser's own promises) is a bug.
// SOURCES: harness/common/units.cpp harness/common/text.cpp
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "harness/common/text.hpp"
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
        // What format_bytes prints (3 significant digits) parses back to within 0.5 %, or is
        // refused as not a whole number of bytes (1.27KiB); never anything else.
        try {
            const double back = static_cast<double>(suite::parse_bytes(suite::format_bytes(b)));
            check(std::abs(back - static_cast<double>(b)) <= 0.005 * static_cast<double>(b));
        } catch (const UsageError& e) {
            check(std::string(e.what()).find("not a whole number of bytes") != std::string::npos);
        }
    } catch (const UsageError&) {
    }
    try {
        const auto counts = suite::parse_count_list(text, "elements", "fuzz");
        check(!counts.empty() && counts.size() <= 1000);
        for (std::size_t i = 0; i < counts.size(); ++i)
            for (std::size_t j = 0; j < i; ++j) check(counts[i] != counts[j]);  // each value once
    } catch (const UsageError&) {
    }
    try {
        const auto names = suite::parse_name_list(text, "--kernel");
        for (const auto& n : names) check(!n.empty());
    } catch (const UsageError&) {
    }
    if (const auto v = suite::whole_number(text)) {  // digits only: the value is the text without its leading zeros
        const auto first = text.find_first_not_of('0');
        check(std::to_string(*v) == (first == std::string::npos ? "0" : text.substr(first)));
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
