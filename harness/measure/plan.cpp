#include "harness/measure/plan.hpp"

#include <algorithm>
#include <cctype>
#include <map>

#include <omp.h>

#include "harness/common/output_file.hpp"
#include "harness/common/units.hpp"

namespace suite {
namespace {

// The default sweep, as data: which kernels, in which patterns. sin-add random is left out
// (ask for it): at a DRAM size it alone would take most of the 2 minutes the sweep may last.
const std::vector<std::pair<std::string, std::vector<std::string>>> default_sweep = {
    {"copy", {"sequential"}},    {"triad", {"sequential"}}, {"add", {"sequential", "random"}},
    {"sin-add", {"sequential"}}, {"latency", {"random"}},
};

Access parse_access(const std::string& text, const std::string& option) {
    Access a;
    if (text.rfind("strided", 0) != 0) {
        a.name = text;
        return a;
    }
    a.name = "strided";
    if (text.size() < 9 || text[7] != ':')
        throw UsageError("--" + option + "=" + text + ": strided needs a stride in elements, e.g. strided:8");
    const auto stride = whole_number(text.substr(8), 1000000000);
    if (!stride || *stride < 1)
        throw UsageError(
            "--" + option + "=" + text +
            ": the stride must be a positive whole number of elements, at most 1000000000, e.g. strided:8");
    a.stride = *stride;
    return a;
}

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

// "phases", "strategies"; "particles" is its own plural ("kernels with particles").
std::string plural(const std::string& noun) {
    if (noun == "particles") return "particle orders";
    return noun.back() == 'y' ? noun.substr(0, noun.size() - 1) + "ies" : noun + "s";
}

// The names a kernel's variant option takes, each with the variant it stands for: the variants but
// "" and the store ones, and the plain kernel by its name ("all" for phases, or plain_variant_name).
std::vector<std::pair<std::string, std::string>> option_choices(const KernelInfo& info) {
    std::vector<std::pair<std::string, std::string>> out;
    for (const auto& v : info.variants)
        if (!v.empty() && !is_store_variant(v)) out.push_back({v, v});
    const bool plain = std::find(info.variants.begin(), info.variants.end(), "") != info.variants.end();
    if (!out.empty() && plain && info.variant_option == "phase")
        out.insert(out.begin(), {"all", ""});
    else if (!out.empty() && plain && !info.plain_variant_name.empty())
        out.insert(out.begin(), {info.plain_variant_name, ""});
    return out;
}

std::vector<std::string> first_of(const std::vector<std::pair<std::string, std::string>>& pairs) {
    std::vector<std::string> out;
    for (const auto& p : pairs) out.push_back(p.first);
    return out;
}

// The variants of one kernel to plan, each with the name it was given by (its option's name, or
// the variant itself when defaulted); `named` says whether the user chose them.
struct Variants {
    std::vector<std::pair<std::string, std::string>> list;  // {name as typed, variant}
    bool named = false;
    std::string option;  // "--strategy=serial,coloured" when named
};

Variants plan_variants(const KernelInfo& info, const std::string& stores_variant,
                       const std::vector<std::pair<std::string, std::string>>& options) {
    Variants out;
    for (const auto& [option, text] : options) {
        if (text.empty()) continue;
        const auto choices = option_choices(info);
        if (info.variant_option != option || choices.empty()) {
            std::vector<std::string> with;
            for (const auto& e : kernels())
                if (e.info.variant_option == option && !option_choices(e.info).empty()) with.push_back(e.info.name);
            throw UsageError("kernel '" + info.name + "' has no " + plural(option) + ", so --" + option +
                             " does not apply" + (choices.empty() ? "" : " (it takes --" + info.variant_option + ")") +
                             "; kernels with " + plural(option) + ": " +
                             (with.empty() ? std::string("none") : join(with, ", ")));
        }
        out.named = true;
        out.option = "--" + option + "=" + text;
        for (const auto& name : parse_name_list(text, "--" + option)) {
            auto it = std::find_if(choices.begin(), choices.end(), [&](const auto& c) { return c.first == name; });
            if (it == choices.end()) {
                // A name a kernel has retired: its new one (MPM's unsorted particles are shuffled).
                std::string hint = option == "particles" && name == "unsorted" ? std::string("shuffled")
                                                                               : nearest(name, first_of(choices));
                throw UsageError("kernel '" + info.name + "' has no " +
                                 (option == "particles" ? "particle order" : option) + " '" + name + "'" +
                                 (hint.empty() ? "" : " (did you mean '" + hint + "'?)") + "; " + plural(option) +
                                 ": " + join(first_of(choices), ", "));
            }
            out.list.push_back(*it);
        }
    }
    if (!out.named) {
        if (stores_variant.empty() && !info.default_variants.empty())
            for (const auto& v : info.default_variants) out.list.push_back({v, v});
        else
            out.list.push_back({stores_variant, stores_variant});
    }
    return out;
}

}  // namespace

Plan make_plan(const RunOptions& o, const Topology& topo, const EnergyOpener& open_energy) {
    Plan plan;
    plan.quiet = o.quiet;
    plan.dry_run = o.dry_run;

    // Kernels, each with the patterns or orderings asked for ("" = the kernel's default).
    std::vector<std::pair<const KernelEntry*, std::vector<std::string>>> ks;
    const bool use_default_sweep = o.kernels.empty();
    std::vector<std::pair<std::string, std::vector<std::string>>> wanted;
    if (use_default_sweep)
        wanted = default_sweep;
    else
        for (const auto& name : parse_name_list(o.kernels, "--kernel")) wanted.push_back({name, {}});
    for (const auto& [name, defaults] : wanted) {
        const KernelEntry* k = find_kernel(name);
        if (!k) {
            std::string hint = nearest(name, kernel_names());
            throw UsageError("unknown kernel '" + name + "'" + (hint.empty() ? "" : " (did you mean '" + hint + "'?)") +
                             "; kernels: " + join(kernel_names(), ", ") + " (see ./suite list)");
        }
        ks.push_back({k, defaults});
    }

    // Output.
    if (!o.format.empty() && o.format != "table" && o.format != "json" && o.format != "csv" && o.format != "gbench")
        throw UsageError("unknown --format '" + o.format +
                         "'; accepted: table, json, csv, gbench (Google Benchmark's JSON)");
    if (!o.out.empty()) {
        if (o.format == "table")
            throw UsageError("--format=table cannot be written to a file; use json or csv (or gbench) with --out");
        plan.out_path = o.out;
        const bool csv_name = o.out.size() > 4 && o.out.substr(o.out.size() - 4) == ".csv";
        plan.format = o.format.empty() ? (csv_name ? "csv" : "json") : o.format;
    } else {
        plan.format = o.format.empty() ? "table" : o.format;
    }

    // Threads and pinning.
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

    std::string thp_note;
    plan.settings.hugepages = parse_hugepages(o.hugepages, "/sys/kernel/mm/transparent_hugepage/enabled", &thp_note);
    if (!thp_note.empty()) plan.notes.push_back(thp_note);

    // Placement, resolved now for every team size, so that "remote" fails before any point runs.
    plan.settings.placement = parse_placement(o.placement, topo);
    if (plan.settings.placement.kind != PlacementKind::local)
        for (const auto& [k, defaults] : ks)
            if (k->info.heap_arrays)
                throw UsageError(
                    "kernel '" + k->info.name +
                    "' keeps its arrays in ordinary heap memory, not in the harness's arena, so --placement=" +
                    plan.settings.placement.text + " cannot place them; give --placement=local (the default) for it");
    std::map<int, MemoryPolicy> policies;
    for (int t : threads)
        policies[t] = resolve_policy(plan.settings.placement, topo, planned_cpus(topo, plan.settings.pin, t));

    // Repetitions.
    if (o.reps == 0 || o.reps < -1)
        throw UsageError("--reps=" + std::to_string(o.reps) + ": at least 1 counted repetition is needed");
    if (o.reps > 10000000) throw UsageError("--reps=" + std::to_string(o.reps) + " is too many; at most 10000000");
    plan.settings.reps = o.reps > 0 ? o.reps : 0;
    if (!(o.min_time > 0) || o.min_time > 3600)
        throw UsageError("--min-time must be more than 0 and at most 3600 seconds");
    plan.settings.min_time_s = o.min_time;
    plan.settings.seed = o.seed;

    // Instruments: an unknown event or backend is a usage error; one that cannot measure here is
    // recorded as unavailable, and said once when it was asked for by name.
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
    if ((o.energy == "sysfs" || o.energy == "perf" || o.energy_baseline > 0) && meter.requested() && !meter.available())
        plan.notes.push_back("energy cannot be measured here: " + meter.reason());

    // Sizes.
    if (!o.size.empty() && !o.sizes.empty())
        throw UsageError("--size and --sizes cannot be used together; give one of them");
    // Without a size, the cache-level sizes are per thread (each thread's share stays in its
    // cache whatever the team), so they are chosen with the thread count, point by point.
    const bool default_size = o.size.empty() && o.sizes.empty();
    // A kernel sized by a count (SizeKind::count) reads the same text as a count of its units, so
    // that a message speaks of what it counts, not of bytes.
    auto given_sizes = [&](const KernelInfo& info) -> std::vector<std::uint64_t> {
        if (info.size_kind == SizeKind::count) {
            const std::string noun = info.unit + "s";
            return o.size.empty() ? parse_count_list(o.sizes, noun, info.name)
                                  : std::vector<std::uint64_t>{parse_count(o.size, noun, info.name)};
        }
        return o.size.empty() ? parse_size_list(o.sizes) : std::vector<std::uint64_t>{parse_bytes(o.size)};
    };
    auto sizes_for = [&](const KernelInfo& info, int t) {
        return default_size ? (info.default_count ? std::vector<std::uint64_t>{info.default_count}
                                                  : default_sizes(topo, t, o.measured))
                            : given_sizes(info);
    };

    // Stores: "nt" or "rep" is a variant of the kernels that have it (is_store_variant).
    if (o.stores != "default" && !is_store_variant(o.stores))
        throw UsageError("unknown --stores '" + o.stores + "'; accepted: default, nt, rep");
    const std::string variant = o.stores == "default" ? "" : o.stores;
    std::vector<std::string> with_variant;
    for (const auto& e : kernels())
        if (std::ranges::count(e.info.variants, variant)) with_variant.push_back(e.info.name);

    // Kernels on a mesh are sized by it (KernelEntry::mesh_elements).
    std::vector<std::string> on_mesh;
    for (const auto& e : kernels())
        if (e.mesh_elements) on_mesh.push_back(e.info.name);

    // Parameters: --NAME=X, a finite number, for a parameter at least one selected kernel
    // declares; each kernel gets its declared ones, at their defaults unless given.
    Params given_params;
    for (const auto& [name, text] : o.params) {
        std::vector<std::string> takers;
        for (const auto& e : kernels())
            for (const auto& p : e.info.params)
                if (p.name == name) takers.push_back(e.info.name);
        if (takers.empty()) throw UsageError("--" + name + ": no kernel takes a parameter of that name");
        given_params[name] = parse_param(name, text);
        bool applies = false;
        std::vector<std::string> selected;
        for (const auto& [k, defaults] : ks) {
            selected.push_back("'" + k->info.name + "'");
            for (const auto& p : k->info.params) applies = applies || p.name == name;
        }
        if (!applies)
            throw UsageError("--" + name + " does not apply to " + (selected.size() == 1 ? "kernel " : "kernels ") +
                             join(selected, ", ") + "; kernels that take it: " + join(takers, ", "));
    }
    if (!o.mesh.empty()) {
        if (!default_size)
            throw UsageError(
                "--mesh and --size/--sizes cannot be used together: the mesh gives the size (its element count)");
        for (const auto& [k, defaults] : ks)
            if (!k->mesh_elements)
                throw UsageError(
                    "kernel '" + k->info.name +
                    "' does not run on a mesh, so --mesh does not apply; kernels on a mesh: " + join(on_mesh, ", "));
    }

    // The points: each kernel takes the patterns or orderings of its own axis.
    const std::vector<std::string> given_patterns =
        o.patterns.empty() ? std::vector<std::string>{} : parse_name_list(o.patterns, "--pattern");
    const std::vector<std::string> given_orderings =
        o.orderings.empty() ? std::vector<std::string>{} : parse_name_list(o.orderings, "--ordering");
    for (const auto& [k, defaults] : ks) {
        const KernelInfo& info = k->info;
        const bool by_pattern = info.axis == AccessAxis::pattern;
        const char* axis = by_pattern ? "pattern" : "ordering";
        if (by_pattern && !given_orderings.empty())
            throw UsageError("kernel '" + info.name + "' takes --pattern, not --ordering=" + o.orderings +
                             " (orderings are for application kernels)");
        if (!by_pattern && !given_patterns.empty())
            throw UsageError("kernel '" + info.name + "' takes --ordering, not --pattern=" + o.patterns);
        std::vector<std::string> texts = by_pattern ? given_patterns : given_orderings;
        if (texts.empty()) texts = defaults.empty() ? std::vector<std::string>{info.accesses.front()} : defaults;
        if (!variant.empty() && std::find(info.variants.begin(), info.variants.end(), variant) == info.variants.end())
            throw UsageError("--stores=" + variant + ": kernel '" + info.name + "' has no " +
                             (variant == "nt" ? "non-temporal-store" : "string-instruction") +
                             " variant; those that do: " +
                             (with_variant.empty() ? std::string("none in this build") : join(with_variant, ", ")));
        // --phase and --strategy pick variants of the kernels that have them; without, the
        // kernel's default variants run.
        const Variants vs = plan_variants(
            info, variant,
            {{"phase", o.phases}, {"strategy", o.strategies}, {"particles", o.particles}, {"isa", o.isas}});
        // A variant on one thread: refused when named with more threads asked for by --threads,
        // else planned for one thread only.
        if (vs.named && !o.threads.empty() && most_threads > 1)
            for (const auto& [name, v] : vs.list)
                if (single_thread_only(info, v))
                    throw UsageError(vs.option + ": " + info.variant_option + " '" + name + "' of kernel '" +
                                     info.name + "' runs on one thread, but --threads=" + o.threads +
                                     " asks for up to " + std::to_string(most_threads) +
                                     "; give --threads=1, or leave '" + name + "' out");
        std::vector<std::string> kernel_variants;
        for (const auto& [name, v] : vs.list) kernel_variants.push_back(v);
        auto team_sizes = [&](const std::string& v) {
            if (!single_thread_only(info, v)) return threads;
            return std::find(threads.begin(), threads.end(), 1) != threads.end() ? std::vector<int>{1}
                                                                                 : std::vector<int>{};
        };
        Params kparams = default_params(info);
        for (const auto& [name, value] : given_params)
            if (kparams.count(name)) kparams[name] = value;
        // A kernel's refusal names a parameter by its value as a number (--cg-max=1e+300); the
        // user reads it as typed (--cg-max=1e300).
        const auto validate = [&](const KernelConfig& cfg) {
            try {
                k->validate(cfg);
            } catch (const UsageError& e) {
                std::string what = e.what();
                for (const auto& [name, text] : o.params) {
                    if (!kparams.count(name)) continue;
                    const std::string shown = "--" + name + "=" + param_text(kparams.at(name)),
                                      typed = "--" + name + "=" + text;
                    for (auto at = what.find(shown); at != std::string::npos; at = what.find(shown, at + typed.size()))
                        if (at + shown.size() == what.size() ||
                            (!std::isalnum(static_cast<unsigned char>(what[at + shown.size()])) &&
                             what[at + shown.size()] != '.'))
                            what.replace(at, shown.size(), typed);
                }
                throw UsageError(what);
            }
        };
        const std::size_t points_before = plan.points.size();
        // Its meshes: --mesh, or the kernel's defaults when no size is given either; "" = sized by --size.
        std::vector<std::string> meshes{""};
        if (k->mesh_elements && (!o.mesh.empty() || default_size))
            meshes = o.mesh.empty() ? k->default_meshes : std::vector<std::string>{o.mesh};
        std::vector<std::string> labels;  // strided:8 and strided:08 are the same pattern
        for (const auto& text : texts) {
            Access a = parse_access(text, axis);
            if (std::find(labels.begin(), labels.end(), a.label()) != labels.end())
                throw UsageError("--" + std::string(axis) + "=" + (by_pattern ? o.patterns : o.orderings) + " names " +
                                 a.label() + " twice; give each once");
            labels.push_back(a.label());
            if (std::find(info.accesses.begin(), info.accesses.end(), a.name) == info.accesses.end()) {
                std::string hint = nearest(a.name, info.accesses);
                throw UsageError("kernel '" + info.name + "' has no " + axis + " '" + text + "'" +
                                 (hint.empty() ? "" : " (did you mean '" + hint + "'?)") +
                                 "; it accepts: " + join(info.accesses, ", "));
            }
            for (const auto& kv : kernel_variants)
                for (const auto& mesh : meshes) {
                    if (!mesh.empty()) {
                        const std::uint64_t size = k->mesh_elements(mesh);
                        for (int t : team_sizes(kv)) {
                            KernelConfig cfg{a, kv, size, plan.settings.seed, t, mesh, kparams};
                            validate(cfg);
                            plan.points.push_back({k, a, kv, size, t, mesh, kparams});
                        }
                        continue;
                    }
                    for (std::size_t s = 0; s < sizes_for(info, 1).size(); ++s)
                        for (int t : team_sizes(kv)) {
                            const std::uint64_t size = sizes_for(info, t)[s];
                            KernelConfig cfg{a, kv, size, plan.settings.seed, t, "", kparams};
                            validate(cfg);
                            plan.points.push_back({k, a, kv, size, t, "", kparams});
                        }
                }
        }
        if (plan.points.size() == points_before &&
            std::all_of(kernel_variants.begin(), kernel_variants.end(),
                        [&](const std::string& v) { return single_thread_only(info, v); }))
            throw UsageError("kernel '" + info.name + "': every " + info.variant_option + " planned (" +
                             join(first_of(vs.list), ", ") + ") runs on one thread, and --threads=" + o.threads +
                             " does not ask for one; add 1 to --threads");
    }

    // Memory: refuse before allocating anything.
    for (const auto& p : plan.points) {
        if (p.kernel->info.size_kind != SizeKind::bytes) continue;
        const MemoryPolicy& policy = policies.at(p.threads);
        const std::uint64_t available = available_memory_bytes(policy);
        if (p.size > available)
            throw UsageError("size " + format_bytes(p.size) + " is larger than the memory available (" +
                             format_bytes(available) +
                             (policy.node >= 0 ? " free on node " + std::to_string(policy.node) : std::string()) + ")");
    }

    // A DRAM figure needs every array well beyond the last-level cache; say so when the largest
    // size cannot give that (the default size is capped at 1 GiB).
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

    // Last, as it creates (and removes) a probe file: nothing is written before all else is
    // checked. The run claims the file (lock, inputs) before it measures: app/suite/run.cpp.
    if (!o.out.empty()) check_output_target(o.out, "--out");
    return plan;
}

}  // namespace suite
