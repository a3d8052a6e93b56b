#pragma once
// The `context` of a result document: what machine, what build, what settings, and which
// instruments could measure here (with the reason when one could not).
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "harness/topology.hpp"

namespace suite {

// Reads one line of a sysfs/procfs file; "" when it cannot be read.
std::string read_first_line(const std::string& path);

// "always [madvise] never" -> "madvise".
std::string bracketed_choice(const std::string& line);

nlohmann::json build_context(const Topology& topo, const std::vector<std::string>& argv);

}  // namespace suite
