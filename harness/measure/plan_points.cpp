// The points of each kernel (a section of make_plan: plan_parts.hpp): its patterns or orderings,
// variants, meshes or sizes and thread counts, each validated by the kernel before it is planned.
#include <algorithm>
#include <cctype>

#include "harness/common/did_you_mean.hpp"
#include "harness/common/text.hpp"
#include "harness/common/units.hpp"
#include "harness/kernel/patterns.hpp"
#include "harness/measure/plan_parts.hpp"

namespace suite::plan_parts {
namespace {

// "NAME" or, for a pattern that takes a stride, "NAME:S".
Access parse_access(const std::string& text, const std::string& option) {
    Access a;
    a.name = text;
    for (const auto& c : access_patterns().all()) {
        if (!c.what.takes_stride || text.rfind(c.name, 0) != 0) continue;
        const std::string example = c.name + ":8";
        a.name = c.name;
        if (text.size() < c.name.size() + 2 || text[c.name.size()] != ':')
            throw UsageError("--" + option + "=" + text + ": " + c.name + " needs a stride in elements, e.g. " +
                             example);
        const auto stride = whole_number(text.substr(c.name.size() + 1), 1000000000);
        if (!stride || *stride < 1)
            throw UsageError("--" + option + "=" + text +
                             ": the stride must be a positive whole number of elements, at most 1000000000, e.g. " +
                             example);
        a.stride = *stride;
    }
    return a;
}

// The sizes of a kernel's points at `t` threads: as given (a kernel sized by a count reads the
// text as a count of its units, so that a message speaks of what it counts), or by default its
// own count or the cache-level sizes, which are per thread and so chosen point by point.
std::vector<DefaultSize> sizes_for(const RunOptions& o, const Topology& topo, const KernelInfo& info, int t) {
    const auto given = [](const std::vector<std::uint64_t>& sizes) {
        std::vector<DefaultSize> out;
        for (auto s : sizes) out.push_back({s, {}});
        return out;
    };
    if (o.size.empty() && o.sizes.empty())
        return info.default_count ? given({info.default_count}) : default_points(topo, t, o.measured);
    if (info.size_kind == SizeKind::count) {
        const std::string noun = info.unit + "s";
        return given(o.size.empty() ? parse_count_list(o.sizes, noun, info.name)
                                    : std::vector<std::uint64_t>{parse_count(o.size, noun, info.name)});
    }
    return given(o.size.empty() ? parse_size_list(o.sizes) : std::vector<std::uint64_t>{parse_bytes(o.size)});
}

// The size of `t` threads that stands where `first` stands at one thread: the same role, or for
// sizes given, the same position. None when the role has no size of its own at `t` (an L3/2
// that the team's share of L2 already reaches).
const DefaultSize* same_place(const std::vector<DefaultSize>& at_t, const DefaultSize& first, std::size_t position) {
    if (first.role.name.empty()) return position < at_t.size() ? &at_t[position] : nullptr;
    for (const auto& d : at_t)
        if (d.role.name == first.role.name) return &d;
    return nullptr;
}

// The kernel's check of one configuration. Its refusal names a parameter by its value as a number
// (--cg-max=1e+300); the user reads it as typed (--cg-max=1e300).
void validate(const RunOptions& o, const KernelEntry& k, const Params& kparams, const KernelConfig& cfg) {
    try {
        k.validate(cfg);
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
}

// A kernel takes the option of its own axis only.
void check_axis(const RunOptions& o, const KernelInfo& info) {
    const bool by_pattern = info.axis == AccessAxis::pattern;
    if (by_pattern && !o.orderings.empty())
        throw UsageError("kernel '" + info.name + "' takes --pattern, not --ordering=" + o.orderings +
                         " (orderings are for application kernels)");
    if (!by_pattern && !o.patterns.empty())
        throw UsageError("kernel '" + info.name + "' takes --ordering, not --pattern=" + o.patterns);
}

// The patterns or orderings of one kernel: as given on its own axis, else the sweep's, else its
// first; each parsed, once, and one the kernel accepts.
std::vector<Access> kernel_accesses(const RunOptions& o, const PlannedKernel& k) {
    const KernelInfo& info = k.entry->info;
    const bool by_pattern = info.axis == AccessAxis::pattern;
    const char* axis = by_pattern ? "pattern" : "ordering";
    const std::string& given = by_pattern ? o.patterns : o.orderings;
    std::vector<std::string> texts =
        given.empty() ? std::vector<std::string>{} : parse_name_list(given, "--" + std::string(axis));
    if (texts.empty()) texts = k.accesses.empty() ? std::vector<std::string>{info.accesses.front()} : k.accesses;
    std::vector<Access> out;
    std::vector<std::string> labels;  // strided:8 and strided:08 are the same pattern
    for (const auto& text : texts) {
        Access a = parse_access(text, axis);
        if (std::find(labels.begin(), labels.end(), a.label()) != labels.end())
            throw UsageError("--" + std::string(axis) + "=" + given + " names " + a.label() + " twice; give each once");
        labels.push_back(a.label());
        if (std::find(info.accesses.begin(), info.accesses.end(), a.name) == info.accesses.end()) {
            std::string hint = nearest(a.name, info.accesses);
            throw UsageError("kernel '" + info.name + "' has no " + axis + " '" + text + "'" +
                             (hint.empty() ? "" : " (did you mean '" + hint + "'?)") +
                             "; it accepts: " + join(info.accesses, ", "));
        }
        out.push_back(a);
    }
    return out;
}

}  // namespace

// --NAME=X, a finite number, for a parameter at least one selected kernel declares.
Params plan_parameters(const RunOptions& o, const std::vector<PlannedKernel>& ks) {
    Params given;
    for (const auto& [name, text] : o.params) {
        std::vector<std::string> takers;
        for (const auto& e : kernels())
            for (const auto& p : e.info.params)
                if (p.name == name) takers.push_back(e.info.name);
        if (takers.empty()) throw UsageError("--" + name + ": no kernel takes a parameter of that name");
        given[name] = parse_param(name, text);
        bool applies = false;
        std::vector<std::string> selected;
        for (const auto& k : ks) {
            selected.push_back("'" + k.entry->info.name + "'");
            for (const auto& p : k.entry->info.params) applies = applies || p.name == name;
        }
        if (!applies)
            throw UsageError("--" + name + " does not apply to " + (selected.size() == 1 ? "kernel " : "kernels ") +
                             join(selected, ", ") + "; kernels that take it: " + join(takers, ", "));
    }
    return given;
}

// Kernels on a mesh are sized by it (KernelEntry::mesh_elements); --mesh is for them alone.
void check_mesh(const RunOptions& o, const std::vector<PlannedKernel>& ks, bool default_size) {
    if (o.mesh.empty()) return;
    std::vector<std::string> on_mesh;
    for (const auto& e : kernels())
        if (e.mesh_elements) on_mesh.push_back(e.info.name);
    if (!default_size)
        throw UsageError(
            "--mesh and --size/--sizes cannot be used together: the mesh gives the size (its element count)");
    for (const auto& k : ks)
        if (!k.entry->mesh_elements)
            throw UsageError(
                "kernel '" + k.entry->info.name +
                "' does not run on a mesh, so --mesh does not apply; kernels on a mesh: " + join(on_mesh, ", "));
}

void plan_kernel_points(const RunOptions& o, const Topology& topo, const PlannedKernel& k, const PointAxes& axes,
                        Plan& plan) {
    const KernelInfo& info = k.entry->info;
    check_axis(o, info);
    const std::string& variant = axes.store_variant;
    if (!variant.empty() && std::find(info.variants.begin(), info.variants.end(), variant) == info.variants.end())
        throw UsageError(
            "--stores=" + variant + ": kernel '" + info.name + "' has no " +
            (variant == "nt" ? "non-temporal-store" : "string-instruction") + " variant; those that do: " +
            (axes.with_variant.empty() ? std::string("none in this build") : join(axes.with_variant, ", ")));
    // --phase and --strategy pick variants of the kernels that have them; without, the
    // kernel's default variants run.
    const Variants vs = plan_variants(
        info, variant, {{"phase", o.phases}, {"strategy", o.strategies}, {"particles", o.particles}, {"isa", o.isas}});
    // A variant on one thread: refused when named with more threads asked for by --threads,
    // else planned for one thread only.
    if (vs.named && !o.threads.empty() && axes.most_threads > 1)
        for (const auto& [name, v] : vs.list)
            if (single_thread_only(info, v))
                throw UsageError(vs.option + ": " + info.variant_option + " '" + name + "' of kernel '" + info.name +
                                 "' runs on one thread, but --threads=" + o.threads + " asks for up to " +
                                 std::to_string(axes.most_threads) + "; give --threads=1, or leave '" + name + "' out");
    auto team_sizes = [&](const std::string& v) {
        if (!single_thread_only(info, v)) return axes.threads;
        return std::find(axes.threads.begin(), axes.threads.end(), 1) != axes.threads.end() ? std::vector<int>{1}
                                                                                            : std::vector<int>{};
    };
    const std::vector<Access> accesses = kernel_accesses(o, k);
    Params kparams = default_params(info);
    for (const auto& [name, value] : axes.parameters)
        if (kparams.count(name)) kparams[name] = value;
    const std::size_t points_before = plan.points.size();
    auto add = [&](const Access& a, const std::string& kv, std::uint64_t size, int t, const std::string& mesh,
                   const SizeRole& role) {
        validate(o, *k.entry, kparams, KernelConfig{a, kv, size, plan.settings.seed, t, mesh, kparams});
        plan.points.push_back({k.entry, a, kv, size, t, mesh, kparams, role});
    };
    // Its meshes: --mesh, or the kernel's defaults when no size is given either; "" = sized by --size.
    std::vector<std::string> meshes{""};
    if (k.entry->mesh_elements && (!o.mesh.empty() || axes.default_size))
        meshes = o.mesh.empty() ? k.entry->default_meshes : std::vector<std::string>{o.mesh};
    for (const auto& a : accesses)
        for (const auto& [name, kv] : vs.list)
            for (const auto& mesh : meshes) {
                if (!mesh.empty()) {
                    const std::uint64_t size = k.entry->mesh_elements(mesh);
                    for (int t : team_sizes(kv)) add(a, kv, size, t, mesh, {});
                    continue;
                }
                const std::vector<DefaultSize> at_one = sizes_for(o, topo, info, 1);
                for (std::size_t s = 0; s < at_one.size(); ++s)
                    for (int t : team_sizes(kv)) {
                        const std::vector<DefaultSize> at_t = sizes_for(o, topo, info, t);
                        if (const DefaultSize* d = same_place(at_t, at_one[s], s)) add(a, kv, d->bytes, t, "", d->role);
                    }
            }
    if (plan.points.size() == points_before &&
        std::all_of(vs.list.begin(), vs.list.end(), [&](const auto& v) { return single_thread_only(info, v.second); }))
        throw UsageError("kernel '" + info.name + "': every " + info.variant_option + " planned (" +
                         join(first_of(vs.list), ", ") + ") runs on one thread, and --threads=" + o.threads +
                         " does not ask for one; add 1 to --threads");
}

}  // namespace suite::plan_parts
