#pragma once
// The `context` of a result document: what machine, what build, what settings, and which
// instruments could measure here (with the reason when one could not).
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "harness/machine/topology.hpp"
#include "harness/measure/instrument_set.hpp"

namespace suite {

// `bandwidth_convention`: which bytes a kernel's STREAM GB/s counts, as the program that owns the
// kernels says it (context.conventions.bandwidth).
nlohmann::json build_context(const Topology& topo, const std::vector<std::string>& argv, const Instruments& instruments,
                             const std::string& bandwidth_convention);

}  // namespace suite
