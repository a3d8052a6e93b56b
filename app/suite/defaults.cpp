#include "app/suite/defaults.hpp"

namespace suite {

// sin-add random is left out (ask for it): at a DRAM size it alone would take most of the
// 2 minutes the sweep may last.
std::vector<SweepEntry> default_sweep() {
    return {{"copy", {"sequential"}},
            {"triad", {"sequential"}},
            {"add", {"sequential", "random"}},
            {"sin-add", {"sequential"}},
            {"latency", {"random"}}};
}

ProbeOptions probe_options() {
    ProbeOptions o;
    o.latency_kernel = "latency";
    o.latency_pattern = "random";
    o.bandwidth_kernel = "load";
    o.bandwidth_pattern = "sequential";
    return o;
}

// The non-temporal stores bypass the caches, so they can only win in memory; the string
// instructions (rep) win in L2 and beyond, where a CPU with fast strings writes whole lines.
RooflineOptions roofline_options() {
    RooflineOptions o;
    o.ceiling_kernels = {
        {"load", "", true, false},    {"copy", "", false, false},    {"triad", "", false, false},
        {"store", "", false, false},  {"copy", "nt", false, true},   {"triad", "nt", false, true},
        {"store", "nt", false, true}, {"copy", "rep", false, false}, {"store", "rep", false, false},
    };
    o.peak_kernel = "peak-flops";
    o.probe_options = probe_options();
    return o;
}

std::string bandwidth_convention() {
    return "STREAM convention: each array element read or written counts once, 8 B per double; "
           "copy/scale 16 B, add/triad/sin-add 24 B per element; index arrays not counted";
}

}  // namespace suite
