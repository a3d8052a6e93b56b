#pragma once
// Parsing of the human-facing quantities on the command line: byte sizes, size sweeps,
// thread lists. Every parser either returns a value or throws UsageError with a message
// that names the bad text and what is accepted; none of them guesses.
#include <cstdint>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace suite {

// A mistake in what the user asked for: reported as one line on stderr, exit status 2.
struct UsageError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

// "64MiB", "1.5GiB", "512kB", "4096" (bytes). Binary units KiB/MiB/GiB/TiB (also K/M/G),
// decimal units kB/MB/GB/TB. Zero and negative sizes are rejected.
std::uint64_t parse_bytes(std::string_view text);

// "16KiB:1GiB" (x2 steps), "16KiB:1GiB:x1.5", or a comma list "32KiB,1MiB,64MiB".
std::vector<std::uint64_t> parse_size_list(std::string_view text);

// "1,2,4", "1-4", "1-8:2" (step), "all" (= max_threads). Every value in 1..max_threads.
std::vector<int> parse_thread_list(std::string_view text, int max_threads);

// "0,2,4-7": a list of logical CPU (PU) numbers as the OS numbers them.
std::vector<int> parse_cpu_list(std::string_view text);

// 64MiB -> "64MiB"; 1.5 GiB -> "1.5GiB"; 1000 -> "1000B".
std::string format_bytes(std::uint64_t bytes);

// Levenshtein distance, for "did you mean ...?" suggestions.
std::size_t edit_distance(std::string_view a, std::string_view b);
// The candidate nearest to `word`, or "" when none is reasonably close.
std::string nearest(std::string_view word, const std::vector<std::string>& candidates);

std::vector<std::string> split(std::string_view text, char sep);
std::string join(const std::vector<std::string>& parts, std::string_view sep);

}  // namespace suite
