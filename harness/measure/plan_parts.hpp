#pragma once
// The sections of make_plan (plan.cpp), one function each, so that each can be read alone: the
// settings of the run (plan_settings.cpp), the variants a kernel's options pick
// (plan_variants.cpp) and the points of each kernel (plan_points.cpp). Private to measure/.
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "harness/machine/placement.hpp"
#include "harness/measure/plan.hpp"

namespace suite::plan_parts {

// A kernel of the plan with the patterns or orderings asked for by the sweep ("" = its default).
struct PlannedKernel {
    const KernelEntry* entry = nullptr;
    std::vector<std::string> accesses;
};

// What every kernel's points share, decided before any point is made.
struct PointAxes {
    std::vector<int> threads;  // each count once, as asked
    int most_threads = 1;
    bool default_size = true;               // neither --size nor --sizes
    std::string store_variant;              // "" or --stores' "nt" / "rep"
    std::vector<std::string> with_variant;  // the kernels that have store_variant
    Params parameters;                      // --NAME=X: a number, or a named choice's name
};

// plan_settings.cpp
std::vector<PlannedKernel> select_kernels(const RunOptions& o);
void plan_output(const RunOptions& o, Plan& plan);
std::vector<int> plan_threads(const RunOptions& o, const Topology& topo, Plan& plan);
std::map<int, MemoryPolicy> plan_placement(const RunOptions& o, const Topology& topo,
                                           const std::vector<PlannedKernel>& ks, const std::vector<int>& threads,
                                           Plan& plan);
void plan_repetitions(const RunOptions& o, Plan& plan);
void plan_instruments(const RunOptions& o, const Topology& topo, const EnergyOpener& open_energy, Plan& plan);
void check_memory(const Plan& plan, const std::map<int, MemoryPolicy>& policies);
void add_size_notes(const RunOptions& o, const Topology& topo, Plan& plan);

// plan_variants.cpp: the variants of one kernel, each with the name it was given by (its
// option's name, or the variant itself when defaulted); `named` says whether the user chose them.
struct Variants {
    std::vector<std::pair<std::string, std::string>> list;  // {name as typed, variant}
    bool named = false;
    std::string option;  // "--strategy=serial,coloured" when named
};
Variants plan_variants(const KernelInfo& info, const std::string& stores_variant,
                       const std::vector<std::pair<std::string, std::string>>& options);
std::vector<std::string> first_of(const std::vector<std::pair<std::string, std::string>>& pairs);

// plan_points.cpp
Params plan_parameters(const RunOptions& o, const std::vector<PlannedKernel>& ks);
void check_mesh(const RunOptions& o, const std::vector<PlannedKernel>& ks, bool default_size);
void plan_kernel_points(const RunOptions& o, const Topology& topo, const PlannedKernel& k, const PointAxes& axes,
                        Plan& plan);

}  // namespace suite::plan_parts
