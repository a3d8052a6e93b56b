#pragma once
// How `suite compare` writes its figures and ratios, shared by the comparison of files
// (compare.cpp) and the hosts of one MPI run (compare_hosts.cpp), so both read alike.
#include <cmath>
#include <cstdio>
#include <string>

#include "harness/common/stats.hpp"
#include "harness/results/result_file.hpp"

namespace suite {

inline std::string compare_value_text(double v) {
    char buf[32];
    if (v != 0 && (std::fabs(v) >= 1e6 || std::fabs(v) < 1e-2))
        std::snprintf(buf, sizeof buf, "%.3e", v);
    else
        std::snprintf(buf, sizeof buf, v >= 100 ? "%.1f" : v >= 1 ? "%.2f" : "%.3g", v);
    return buf;
}

inline std::string compare_ratio_text(double r) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.3fx", r);
    return buf;
}

inline const Measure* find_measure(const LoadedPoint& p, const std::string& name) {
    for (const auto& m : p.measures)
        if (m.name == name) return &m;
    return nullptr;
}

// Performance of `value` relative to `reference`, both of a figure going `direction`: above 1
// is better, whichever way the figure goes (B/A for a rate, A/B for a time). NAN without both.
inline double performance_ratio(double reference, double value, Direction direction) {
    if (!(reference > 0) || !(value > 0)) return NAN;
    return direction == Direction::higher_is_better ? value / reference : reference / value;
}

}  // namespace suite
