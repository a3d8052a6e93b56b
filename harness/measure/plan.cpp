#include "harness/measure/plan.hpp"

#include <algorithm>

#include "harness/common/output_file.hpp"
#include "harness/common/text.hpp"
#include "harness/common/units.hpp"
#include "harness/kernel/store_variants.hpp"
#include "harness/measure/plan_parts.hpp"

namespace suite {

// Each section is one function of plan_parts.hpp; the order is the order of the checks, so that
// the first problem a user meets is the one named.
Plan make_plan(const RunOptions& o, const Topology& topo, const EnergyOpener& open_energy) {
    using namespace plan_parts;
    Plan plan;
    plan.quiet = o.quiet;
    plan.dry_run = o.dry_run;
    const std::vector<PlannedKernel> ks = select_kernels(o);
    plan_output(o, plan);
    PointAxes axes;
    axes.threads = plan_threads(o, topo, plan);
    axes.most_threads = *std::max_element(axes.threads.begin(), axes.threads.end());
    const std::map<int, MemoryPolicy> policies = plan_placement(o, topo, ks, axes.threads, plan);
    plan_repetitions(o, plan);
    plan_instruments(o, topo, open_energy, plan);

    if (!o.size.empty() && !o.sizes.empty())
        throw UsageError("--size and --sizes cannot be used together; give one of them");
    axes.default_size = o.size.empty() && o.sizes.empty();
    // Stores: "nt" or "rep" is a variant of the kernels that have it (is_store_variant).
    // The table refuses a name it does not have; a variant this build lacks is refused with why.
    if (const char* why = store_variants().at(o.stores).what.unavailable; *why != '\0')
        throw UsageError("--stores=" + o.stores + ": " + why +
                         "; this build has: " + join(usable_store_variants(), ", "));
    axes.store_variant = o.stores == "default" ? "" : o.stores;
    for (const auto& e : kernels())
        if (std::ranges::count(e.info.variants, axes.store_variant)) axes.with_variant.push_back(e.info.name);
    axes.parameters = plan_parameters(o, ks);
    check_mesh(o, ks, axes.default_size);

    for (const auto& k : ks) plan_kernel_points(o, topo, k, axes, plan);
    check_memory(plan, policies);
    add_size_notes(o, topo, plan);

    // Last, as it creates (and removes) a probe file: nothing is written before all else is
    // checked. The run claims the file (lock, inputs) before it measures: app/suite/run.cpp.
    if (!o.out.empty()) check_output_target(o.out, "--out");
    return plan;
}

}  // namespace suite
