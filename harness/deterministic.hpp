#pragma once
// `suite deterministic [run options]`: the points of a run measured under valgrind's callgrind
// with its cache simulator, counting only inside the kernel's calls, so that a CI machine
// without a PMU, and with noisy neighbours, still gets figures that repeat exactly: instructions,
// simulated D1 and last-level misses per kernel call. The command runs itself under valgrind;
// the inner run marks each point (harness/callgrind_marks.hpp) and the outer one reads the
// dumps and writes a suite result whose records carry a "callgrind" block.
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

namespace suite {

// One callgrind dump: its label (the client request's) and its event totals by name.
struct CallgrindDump {
    std::string label;
    std::vector<std::pair<std::string, double>> totals;  // "Ir", "Dr", ..., in the file's order
    double get(const std::string& event) const;          // NAN when the dump has no such event
};

// Reads a callgrind output file (format of valgrind 3.x); throws std::runtime_error when it has
// no events line or no totals/summary line.
CallgrindDump parse_callgrind_dump(const std::string& text);

// The record's "callgrind" block from a dump: the counts per kernel call (`calls` calls were
// collected) and how they were obtained.
nlohmann::json callgrind_block(const CallgrindDump& dump, double calls, const std::string& valgrind_version);

// The command: returns the exit status of the run (0, 1 a kernel failed verification,
// 128+signal); throws UsageError for exit status 2.
int cmd_deterministic(const std::vector<std::string>& args, const std::vector<std::string>& full_argv);

}  // namespace suite
