#pragma once
// Parsing of the human-facing quantities on the command line: byte sizes, size sweeps,
// thread lists. Every parser either returns a value or throws UsageError with a message
// that names the bad text and what is accepted; none of them guesses.
#include <cstdint>
#include <cstdio>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "harness/common/usage_error.hpp"

namespace suite {

// A decimal whole number: digits only (no sign, space, point, exponent or unit) and at most
// `hi`; nullopt for anything else, an overflow included. For numbers read from the system as
// much as for those typed.
std::optional<std::uint64_t> whole_number(std::string_view text, std::uint64_t hi = UINT64_MAX);

// The value of option `option` (e.g. "--reps"): a whole number from lo to hi, else a UsageError
// that names the value and the range ("--reps=-1: expected a whole number from 1 to 10000000");
// `about`, if given, is added in parentheses after the range.
std::uint64_t parse_whole(std::string_view text, std::string_view option, std::uint64_t lo, std::uint64_t hi,
                          std::string_view about = {});

// The value of option `option` (e.g. "--tol"): a finite decimal number such as 0.05, -2, 1e-8 or
// 2.5E+3, nothing else (no space, unit, hex, inf or nan, and no value beyond a double's range),
// else a UsageError of one line that names the value and what is accepted.
double parse_finite(std::string_view text, std::string_view option);

// The shortest text that reads back as the same double: 0.05, 1e-08, 12, -3.5.
std::string format_number(double value);
// A figure for people, to `digits` significant digits: 106.1, 0.0417, 2.1e+03.
inline std::string format_significant(double value, int digits) {
    char buf[40];
    std::snprintf(buf, sizeof buf, "%.*g", digits, value);
    return buf;
}

// The seed of every command's random orderings: 0 to 2^64-1, exactly as typed.
std::uint64_t parse_seed(std::string_view text, std::string_view option = "--seed");

// A comma list of names as given, e.g. --kernel=add,triad: every item non-empty and given
// once, else a UsageError naming the option, the list and the item. Every list option follows
// this one rule: a value given twice is refused, never dropped or run twice.
std::vector<std::string> parse_name_list(std::string_view text, std::string_view option);

// "64MiB", "1.5GiB", "512kB", "4096" (bytes). Binary units KiB/MiB/GiB/TiB (also K/M/G),
// decimal units kB/MB/GB/TB. Zero, negative sizes and sizes that are not a whole number of
// bytes ("1.5B", "0.3KiB") are rejected; 1.5KiB is 1536 bytes exactly.
std::uint64_t parse_bytes(std::string_view text);

// "16KiB:1GiB" (x2 steps), "16KiB:1GiB:x1.5", or a comma list "32KiB,1MiB,64MiB". A size given
// twice, or a sweep whose steps round to the same byte count twice, is refused.
std::vector<std::uint64_t> parse_size_list(std::string_view text);

// The size of a kernel sized by a count (SizeKind::count), e.g. "10000": a whole number of
// `noun` (plural, e.g. "elements") from 1 to 10^18, without a unit; `owner` (the kernel) and
// the noun name it in messages.
std::uint64_t parse_count(std::string_view text, std::string_view noun, std::string_view owner);

// The --sizes forms for a kernel sized by a count: "10000", "1000:1000000:x10", "10000,20000",
// each value as parse_count takes it.
std::vector<std::uint64_t> parse_count_list(std::string_view text, std::string_view noun, std::string_view owner);

// "1,2,4", "1-4", "1-8:2" (step), "all" (= max_threads). Every value in 1..max_threads, each
// given once. `limit` says what max_threads is, in messages; empty: the processing units of
// this machine, and 'all' is accepted; otherwise 'all' is refused.
std::vector<int> parse_thread_list(std::string_view text, int max_threads, std::string_view limit = {});

// "0,2,4-7": a list of logical CPU (PU) numbers as the OS numbers them, each given once.
std::vector<int> parse_cpu_list(std::string_view text);

// 64MiB -> "64MiB"; 1.5 GiB -> "1.5GiB"; 1000 -> "1000B".
std::string format_bytes(std::uint64_t bytes);

}  // namespace suite
