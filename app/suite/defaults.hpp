#pragma once
// What suite measures when it is not told, decided here and handed to the engine, which names no
// kernel: the default sweep, the kernels of the roofline's ceilings and of the cache probe, and
// the bytes each kernel's STREAM bandwidth counts. suite-mpi takes the same.
#include <string>
#include <vector>

#include "harness/measure/cache_probe.hpp"
#include "harness/measure/plan.hpp"
#include "harness/measure/roofline.hpp"

namespace suite {

// The kernels and patterns of `./suite` with no --kernel.
std::vector<SweepEntry> default_sweep();

// The cache probe's pointer chase and read-only stream, on otherwise default options.
ProbeOptions probe_options();

// The roofline's kernels (ceiling_kernels, peak_kernel, probe_options), on otherwise default options.
RooflineOptions roofline_options();

// context.conventions.bandwidth: the bytes per element each kernel's STREAM GB/s counts.
std::string bandwidth_convention();

}  // namespace suite
