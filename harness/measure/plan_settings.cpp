// The settings of a run, each section of make_plan one function (plan_parts.hpp): the kernels,
// the output, threads and pinning, placement, repetitions, instruments, memory and the notes
// on the sizes.
#include <algorithm>

#include <omp.h>

#include "harness/common/did_you_mean.hpp"
#include "harness/common/text.hpp"
#include "harness/common/units.hpp"
#include "harness/measure/plan_parts.hpp"

namespace suite::plan_parts {
namespace {

// The CPUs a team of `threads` may run on under `pin`, before it exists.
std::vector<int> planned_cpus(const Topology& topo, const PinSpec& pin, int threads) {
    std::vector<int> order = pin_order(topo, pin);
    if (pin.mode == PinMode::none) {
        for (const auto& p : topo.pus) order.push_back(p.os_index);
        return order;
    }
    order.resize(std::min<std::size_t>(order.size(), static_cast<std::size_t>(threads)));
    return order;
}

}  // namespace

// The kernels named by --kernel, or the program's default sweep with its patterns.
std::vector<PlannedKernel> select_kernels(const RunOptions& o) {
    std::vector<SweepEntry> wanted;
    if (o.kernels.empty())
        wanted = o.default_sweep;
    else
        for (const auto& name : parse_name_list(o.kernels, "--kernel")) wanted.push_back({name, {}});
    if (wanted.empty()) throw UsageError("no kernel to run: give --kernel=NAME (see ./suite list)");
    std::vector<PlannedKernel> ks;
    for (const auto& [name, accesses] : wanted) {
        const KernelEntry* k = find_kernel(name);
        if (!k) {
            std::string hint = nearest(name, kernel_names());
            throw UsageError("unknown kernel '" + name + "'" + (hint.empty() ? "" : " (did you mean '" + hint + "'?)") +
                             "; kernels: " + join(kernel_names(), ", ") + " (see ./suite list)");
        }
        ks.push_back({k, accesses});
    }
    return ks;
}

void plan_output(const RunOptions& o, Plan& plan) {
    const Choice<OutputFormatBehaviour>* asked = o.format.empty() ? nullptr : &output_formats().at(o.format);
    if (o.out.empty()) {
        plan.format = asked ? asked->what.format : OutputFormat::table;
        return;
    }
    if (asked && !asked->what.to_file)
        throw UsageError("--format=" + asked->name + " cannot be written to a file; use " + file_format_names() +
                         " with --out");
    plan.out_path = o.out;
    if (asked) {
        plan.format = asked->what.format;
        return;
    }
    plan.format = OutputFormat::json;  // unless the file's name ends as a format's files do
    for (const auto& c : output_formats().all()) {
        const std::string& suffix = c.what.out_suffix;
        if (!suffix.empty() && o.out.size() > suffix.size() && o.out.ends_with(suffix)) plan.format = c.what.format;
    }
}

// The thread counts, each once, and the pinning (plan.settings.pin) they run under.
std::vector<int> plan_threads(const RunOptions& o, const Topology& topo, Plan& plan) {
    std::vector<int> threads;
    std::vector<int> asked{1, topo.pu_count()};
    try {
        if (!o.threads.empty()) asked = parse_thread_list(o.threads, topo.pu_count());
    } catch (const UsageError& e) {
        if (!topo.mask_restricted()) throw;
        throw UsageError(std::string(e.what()) + " (this process's CPU mask allows CPUs " +
                         format_cpu_list(topo.mask_cpus) + " of the machine's " +
                         std::to_string(topo.machine_cpus.size()) + ")");
    }
    for (int t : asked)
        if (std::find(threads.begin(), threads.end(), t) == threads.end()) threads.push_back(t);
    plan.settings.pin = parse_pin(o.pin, topo);
    const int most_threads = *std::max_element(threads.begin(), threads.end());
    if (most_threads > omp_get_thread_limit())
        throw UsageError(std::to_string(most_threads) + " threads were asked for but OpenMP allows at most " +
                         std::to_string(omp_get_thread_limit()) + " (OMP_THREAD_LIMIT); ask for fewer or unset it");
    if (plan.settings.pin.mode == PinMode::list && static_cast<int>(plan.settings.pin.cpus.size()) < most_threads)
        throw UsageError("--pin=" + o.pin + " lists " + std::to_string(plan.settings.pin.cpus.size()) +
                         " CPU(s) but up to " + std::to_string(most_threads) +
                         " threads were asked for; list at least one CPU per thread");
    if (plan.settings.pin.mode != PinMode::none && !topo.this_system)
        throw UsageError(
            "the topology is not this machine's (HWLOC_SYNTHETIC or HWLOC_XMLFILE is set), so threads cannot be "
            "pinned; use --pin=none");
    return threads;
}

// Huge pages and placement, resolved now for every team size, so that "remote" fails before any
// point runs: the memory policy of each thread count.
std::map<int, MemoryPolicy> plan_placement(const RunOptions& o, const Topology& topo,
                                           const std::vector<PlannedKernel>& ks, const std::vector<int>& threads,
                                           Plan& plan) {
    std::string thp_note;
    plan.settings.hugepages = parse_hugepages(o.hugepages, "/sys/kernel/mm/transparent_hugepage/enabled", &thp_note);
    if (!thp_note.empty()) plan.notes.push_back(thp_note);
    plan.settings.placement = parse_placement(o.placement, topo);
    if (plan.settings.placement.kind != PlacementKind::local)
        for (const auto& k : ks)
            if (k.entry->info.heap_arrays)
                throw UsageError(
                    "kernel '" + k.entry->info.name +
                    "' keeps its arrays in ordinary heap memory, not in the harness's arena, so --placement=" +
                    plan.settings.placement.text + " cannot place them; give --placement=local (the default) for it");
    std::map<int, MemoryPolicy> policies;
    for (int t : threads)
        policies[t] = resolve_policy(plan.settings.placement, topo, planned_cpus(topo, plan.settings.pin, t));
    return policies;
}

void plan_repetitions(const RunOptions& o, Plan& plan) {
    if (o.reps == 0 || o.reps < -1)
        throw UsageError("--reps=" + std::to_string(o.reps) + ": at least 1 counted repetition is needed");
    if (o.reps > 10000000) throw UsageError("--reps=" + std::to_string(o.reps) + " is too many; at most 10000000");
    plan.settings.reps = o.reps > 0 ? o.reps : 0;
    if (!(o.min_time > 0) || o.min_time > 3600)
        throw UsageError("--min-time must be more than 0 and at most 3600 seconds");
    plan.settings.min_time_s = o.min_time;
    plan.settings.fresh_arrays = o.fresh_arrays;
    plan.settings.seed = o.seed;
}

// An unknown event or backend is a usage error; one that cannot measure here is recorded as
// unavailable, and said once when it was asked for by name.
void plan_instruments(const RunOptions& o, const Topology& topo, const EnergyOpener& open_energy, Plan& plan) {
    if (!(o.energy_baseline >= 0) || o.energy_baseline > 600)
        throw UsageError("--energy-baseline=" + std::to_string(o.energy_baseline) +
                         ": accepted: 0 (none) to 600 seconds");
    plan.instruments = make_instruments(o.counters, o.energy, open_energy);
    plan.instruments.energy_baseline_s = o.energy_baseline;
    for (int level = 4; level >= 1; --level)
        if (const Cache* c = topo.find_cache(level); c && c->line_bytes > 0) {
            plan.instruments.line_bytes = c->line_bytes;
            break;
        }
    const bool named_events = o.counters != "default" && o.counters != "none" && !o.counters.empty();
    if (named_events)
        for (const auto& e : plan.instruments.counters.events)
            if (std::string why = probe_event(e, plan.instruments.access); !why.empty())
                plan.notes.push_back("counter " + e.name + " cannot be counted here: " + why);
    const EnergyInstrument& meter = *plan.instruments.energy;
    // Said when a source was named or idle power asked for: auto may well find none.
    const Choice<EnergyChoice>* choice = energy_backends().find(o.energy);
    if (((choice && choice->what.names_a_source) || o.energy_baseline > 0) && meter.requested() && !meter.available())
        plan.notes.push_back("energy cannot be measured here: " + meter.reason());
}

// Refused before anything is allocated.
void check_memory(const Plan& plan, const std::map<int, MemoryPolicy>& policies) {
    for (const auto& p : plan.points) {
        if (p.kernel->info.size_kind != SizeKind::bytes) continue;
        const MemoryPolicy& policy = policies.at(p.threads);
        const std::uint64_t available = available_memory_bytes(policy);
        if (p.size > available)
            throw UsageError("size " + format_bytes(p.size) + " is larger than the memory available (" +
                             format_bytes(available) +
                             (policy.node >= 0 ? " free on node " + std::to_string(policy.node) : std::string()) + ")");
    }
}

// A DRAM figure needs every array well beyond the last-level cache; say so when the largest
// size cannot give that (the default size is capped at 1 GiB).
void add_size_notes(const RunOptions& o, const Topology& topo, Plan& plan) {
    const bool default_size = o.size.empty() && o.sizes.empty();
    const std::uint64_t llc = effective_llc_bytes(topo, o.measured.llc_total);
    const std::uint64_t largest = default_sizes(topo, 1, o.measured).back();
    const char* which = o.measured.llc_total > 0 && llc == o.measured.llc_total ? "measured" : "reported";
    if (default_size && llc > 0 && largest < 12 * llc)
        plan.notes.push_back("the largest default size, " + format_bytes(largest) + ", is less than 4x the " + which +
                             " last-level cache (" + format_bytes(llc) +
                             ") per array; it may not measure DRAM (see each record's size.smallest_array_over_llc)");
    if (o.probe_caches && o.measured.llc_total == 0 && default_size)
        plan.notes.push_back(
            o.dry_run
                ? "--probe-caches does not run with --dry-run: the default sizes shown follow the reported caches"
                : "the cache probe found no last level below memory: the default sizes follow the reported caches");
}

}  // namespace suite::plan_parts
