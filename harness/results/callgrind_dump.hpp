#pragma once
// What `suite deterministic` (app/suite/deterministic.cpp) reads back from valgrind: the
// callgrind dump of each point, turned into the record's "callgrind" block (counts per kernel
// call under a fixed simulated cache, so that they repeat exactly on any machine).
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

namespace suite {

// Fixed simulated caches (size, associativity, line), so that the counts do not depend on the
// CI machine's caches: a common 32 KiB 8-way L1 and an 8 MiB 16-way last level.
inline constexpr const char* callgrind_sim_i1 = "32768,8,64";
inline constexpr const char* callgrind_sim_d1 = "32768,8,64";
inline constexpr const char* callgrind_sim_ll = "8388608,16,64";

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

}  // namespace suite
