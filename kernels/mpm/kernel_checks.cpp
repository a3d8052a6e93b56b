#include "kernels/mpm/kernel_checks.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <variant>

#include "harness/common/units.hpp"
#include "harness/kernel/arena.hpp"
#include "harness/kernel/blocks.hpp"
#include "kernels/mesh/mesh_spec.hpp"
#include "kernels/mpm/choices.hpp"

namespace suite::mpm {

std::string box_spec_for(std::uint64_t elements) {
    const auto n = static_cast<std::uint64_t>(std::ceil(std::cbrt(static_cast<double>(elements) / 6.0)));
    const std::string k = std::to_string(std::max<std::uint64_t>(n, 2));
    return "box:" + k + "," + k + "," + k;
}

std::uint64_t mesh_elements(const std::string& spec) {
    const mesh::MeshCounts c = mesh::mesh_counts(mesh::parse_mesh_spec(spec));
    if (c.dim != 3) throw UsageError("--mesh=" + spec + ": the MPM kernels need a tetrahedral grid, e.g. box:24,24,24");
    return c.elements;
}

KernelEntry mpm_entry(const std::string& name, const std::string& formula, const std::string& unit, bool strategies,
                      bool sorted_steps) {
    KernelEntry e;
    e.info.name = name;
    e.info.group = "mpm";
    e.info.formula = formula;
    e.info.unit = unit;
    e.info.axis = AccessAxis::ordering;
    e.info.accesses = grid_orderings().names();
    if (strategies) {
        e.info.variants = mpm::strategies().names();
        e.info.variant_option = "strategy";
        e.info.single_thread_variants = {strategy_name(Strategy::serial)};
    } else {
        e.info.variants = particle_orders().names();
        e.info.variant_option = "particles";
        e.info.retired_variants = particle_orders().retired();
    }
    e.info.default_variants = e.info.variants;
    e.info.params = {
        {"ppe", 4, "MPM particles per element of the material's column, a whole number >= 1 (mpm kernels)"},
        {"case", 0, "MPM case: " + cases().accepted() + ", as suite mpm --case (mpm kernels)", cases().names(),
         case_order_v1()},
        {"warm-steps", 5,
         "MPM steps run untimed before the first repetition, under the reordering schedule: a mixed state of the flow "
         "(mpm kernels), 0 to 10000000"}};
    if (sorted_steps)
        e.info.params.push_back({"sort-every",
                                 0,
                                 "MPM particle reordering (sorted, dynamic): auto (when the order has decayed, "
                                 "docs/mpm.md) or every K >= 1 steps; a repetition is K steps, or a fixed number "
                                 "under auto (mpm-step 20, mpm-implicit-step 5)",
                                 {"auto"},
                                 {},
                                 true});
    e.info.size_kind = SizeKind::count;
    e.mesh_elements = mesh_elements;
    e.test_size = 6 * 5 * 5 * 5;
    return e;
}

void validate_mpm(const KernelConfig& cfg, const std::string& kernel, const std::string& spec) {
    for (const char* name : {"ppe", "sort-every"}) {
        if (!cfg.params.count(name)) continue;
        if (std::holds_alternative<std::string>(cfg.params.at(name))) continue;  // sort-every=auto
        const double v = cfg.param(name);
        if (!(v >= 1) || v != std::floor(v) || v > 1e6)
            throw UsageError("--" + std::string(name) + "=" + format_number(v) + " for " + kernel +
                             ": a whole number from 1 to 1000000");
    }
    if (cfg.params.count("warm-steps")) {
        const double v = cfg.param("warm-steps");
        if (!(v >= 0) || v != std::floor(v) || v > 1e7)
            throw UsageError("--warm-steps=" + format_number(v) + " for " + kernel +
                             ": a whole number of untimed steps from 0 to 10000000");
    }
    if (cfg.variant == strategy_name(Strategy::serial) && cfg.threads > 1)
        throw UsageError(kernel + "'s serial strategy runs on one thread, not " + std::to_string(cfg.threads) +
                         "; the parallel ones: atomic, colour, partition");
    const mesh::MeshCounts c = mesh::mesh_counts(mesh::parse_mesh_spec(spec));
    if (c.dim != 3)
        throw UsageError("--mesh=" + spec + " for " + kernel + ": the MPM grid must be tetrahedral, e.g. box:24,24,24");
    // The grid (shape, neighbours, keys while built), the particles at most per_element per
    // element, twice over (verify's copies), and the mesh while it is loaded and ordered.
    const std::uint64_t np = c.elements * static_cast<std::uint64_t>(cfg.param("ppe"));
    const std::uint64_t need =
        state_bytes(c, np, 2, cfg.params.count("dt-multiple") > 0);  // the implicit kernels have dt-multiple
    const std::uint64_t have = available_memory_bytes(MemoryPolicy{});
    if (need > have)
        throw UsageError(kernel + " on --mesh=" + spec + " needs about " + format_bytes(need) + ", more than the " +
                         format_bytes(have) + " of memory available; use a smaller grid");
}

namespace {

// Adds one value at a time with Neumaier's compensation (compensated_sum, and the nodal sums).
struct ExactSum {
    double sum = 0, c = 0;
    void add(double v) {
        const double t = sum + v;
        c += std::fabs(sum) >= std::fabs(v) ? (sum - t) + v : (v - t) + sum;
        sum = t;
    }
    double value() const { return sum + c; }
};

std::string position_mismatch(const Particles& a, const Particles& b, double tol) {
    if (a.size() != b.size()) return std::to_string(a.size()) + " particles against " + std::to_string(b.size());
    std::vector<std::uint32_t> where(b.size());
    for (std::size_t p = 0; p < b.size(); ++p) where[b.id[p]] = static_cast<std::uint32_t>(p);
    double worst = 0;
    std::uint32_t who = 0;
    for (std::size_t p = 0; p < a.size(); ++p) {
        const std::size_t q = where[a.id[p]];
        const double d = std::max({std::fabs(a.x[p] - b.x[q]), std::fabs(a.y[p] - b.y[q]), std::fabs(a.z[p] - b.z[q])});
        if (!(d <= worst)) worst = d, who = a.id[p];
    }
    if (worst <= tol) return "";
    return "particle " + std::to_string(who) + " is " + format_number(worst) +
           " away from its reference position (more than " + format_number(tol) + ")";
}

}  // namespace

int sort_every_of(const KernelConfig& cfg) {
    const ParamValue& v = cfg.params.at("sort-every");
    if (std::holds_alternative<std::string>(v)) return sort_auto;
    return static_cast<int>(std::get<double>(v));
}

std::vector<Fact> reordering_facts(const State& st, const Setup& s, std::uint64_t since) {
    const OrderTracker& t = st.order;
    std::uint64_t decayed = 0, renumbered = 0;
    for (std::size_t i = since; i < t.log.size(); ++i) {
        decayed += t.log[i].cause == ReorderCause::decayed ? 1 : 0;
        renumbered += t.log[i].renumbered ? 1 : 0;
    }
    std::vector<Fact> f{{"reorderings", static_cast<double>(t.count - since), "reorderings in the timed steps"}};
    const bool renumbers = particle_orders().at(s.particles).what.renumbers;
    if (renumbers)
        f.push_back({"renumberings", static_cast<double>(renumbered), "of those that renumbered the grid too"});
    if (s.sort_every == sort_auto) {
        f.push_back({"reorderings-decayed", static_cast<double>(decayed), "reorderings the decay called for"});
        f.push_back({"sort-threshold", s.sort_threshold, "same-element share x steps"});
        if (renumbers)
            f.push_back({"renumber-share", s.renumber_share, "share of the particles outside the renumbered elements"});
    }
    return f;
}

std::string reorderings_text(const State& st, const Setup& s, std::uint64_t since) {
    if (!particle_orders().at(s.particles).what.sorts) return "";
    const OrderTracker& t = st.order;
    std::string out;
    std::size_t shown = 0;
    for (std::size_t i = since; i < t.log.size() && shown < 10; ++i, ++shown)
        out +=
            (out.empty() ? "" : ", ") + std::to_string(t.log[i].step) + " (" + reorder_cause_name(t.log[i].cause) + ")";
    const std::uint64_t all = t.count > since ? t.count - since : 0;
    if (all == 0) return "; no reordering after the timing started";
    return "; reordered after step(s) " + out + (all > shown ? " and " + std::to_string(all - shown) + " more" : "");
}

std::string check_equivalence(const Setup& point) {
    Setup mine = point, ref = point;
    if (point.sort_every != sort_auto) mine.sort_every = std::min(point.sort_every, 2);
    ref.ordering = sfc::as_given_name();
    ref.particles = "seeded";
    ref.strategy = Strategy::serial;
    State a = build(mine), b = build(ref);
    for (int k = 0; k < equivalence_steps; ++k) {
        advance(a, mine);
        advance(b, ref);
    }
    // An implicit step that failed moved nothing: two runs that both failed would agree.
    for (const State* st : {&a, &b})
        if (st->implicit.failed_steps > 0)
            return "a step of the " + std::string(st == &a ? "point's" : "reference") +
                   " run failed: " + st->implicit.failure;
    const std::string m = position_mismatch(a.particles, b.particles, 1e-10);
    return m.empty() ? "" : "after " + std::to_string(equivalence_steps) + " steps, " + m;
}

std::string check_p2g_against_serial(State& st) {
    std::vector<NodeState> mine = st.nodes;
    const ScatterPlan plan = st.plan;
    st.plan = plan_scatter(st.grid, Strategy::serial, 1);
    p2g(st);
    st.plan = plan;
    // st.nodes: the strategy's again (value by value: placed nodes keep their pages); mine: the serial reference
    std::swap_ranges(mine.begin(), mine.end(), st.nodes.begin());
    double scale[3] = {0, 0, 0}, worst[3] = {0, 0, 0};
    ExactSum nodal;
    for (std::uint32_t n = 0; n < st.node_hi; ++n) {
        const double* r = &mine[n].m;
        const double* s = &st.nodes[n].m;
        for (int k = 0; k < 7; ++k) {
            const int g = k == 0 ? 0 : k < 4 ? 1 : 2;
            scale[g] = std::max(scale[g], std::fabs(r[k]));
            worst[g] = std::max(worst[g], std::fabs(r[k] - s[k]));
            if (!std::isfinite(s[k])) return "node " + std::to_string(n) + " holds a value that is not finite";
        }
        nodal.add(s[0]);
    }
    const double sum_m = nodal.value();
    const char* names[3] = {"mass", "momentum", "force"};
    for (int g = 0; g < 3; ++g)
        if (worst[g] > 1e-12 * scale[g])
            return std::string("nodal ") + names[g] + " differs from the serial P2G by " + format_number(worst[g]) +
                   " (largest " + format_number(scale[g]) + ")";
    const double m = mass_by_id(st.particles);
    if (std::fabs(sum_m - m) > 1e-12 * m) return "Σ m_n = " + format_number(sum_m) + " but Σ m_p = " + format_number(m);
    return "";
}

std::string check_g2p_replay(const State& start, const State& now, long calls) {
    State r = start;
    for (long c = 0; c < calls; ++c) g2p(r);
    const Particles& a = r.particles;
    const Particles& b = now.particles;
    for (std::size_t p = 0; p < a.size(); ++p)
        if (a.x[p] != b.x[p] || a.y[p] != b.y[p] || a.z[p] != b.z[p] || a.vx[p] != b.vx[p] || a.vy[p] != b.vy[p] ||
            a.vz[p] != b.vz[p])
            return "particle " + std::to_string(p) + " differs from the serial replay";
    return "";
}

double compensated_sum(const std::vector<double>& v) {
    ExactSum s;
    for (double x : v) s.add(x);
    return s.value();
}

double mass_by_id(const Particles& p) {
    std::vector<double> m(p.size());
    for (std::size_t i = 0; i < p.size(); ++i) m[p.id[i]] = p.mass[i];
    return compensated_sum(m);
}

std::string check_state(State& st, double mass) {
    const Particles& p = st.particles;
    const Grid& g = st.grid;
    for (std::size_t i = 0; i < p.size(); ++i) {
        const double pos[3] = {p.x[i], p.y[i], p.z[i]};
        for (int a = 0; a < 3; ++a)
            if (!(pos[a] >= g.lo[a] && pos[a] <= g.hi[a]))
                return "particle " + std::to_string(p.id[i]) + " is outside the box (or not finite)";
        if (!std::isfinite(p.vx[i] + p.vy[i] + p.vz[i]))
            return "particle " + std::to_string(p.id[i]) + " has a velocity that is not finite";
        double ws = 0;
        for (int k = 0; k < 4; ++k) {
            if (!(p.w[4 * i + k] >= 0))
                return "particle " + std::to_string(p.id[i]) + " has a negative shape function value";
            ws += p.w[4 * i + k];
        }
        if (std::fabs(ws - 1) > 1e-12)
            return "particle " + std::to_string(p.id[i]) + "'s shape functions sum to " + format_number(ws);
    }
    const double now = mass_by_id(p);
    if (now != mass)
        return "the particles' mass is " + format_number(now) + ", not the " + format_number(mass) +
               " they started with";
    p2g(st);
    ExactSum nodal;
    for (std::uint32_t n = 0; n < st.node_hi; ++n) nodal.add(st.nodes[n].m);
    const double sum_m = nodal.value();
    if (std::fabs(sum_m - mass) > 1e-12 * mass)
        return "Σ m_n = " + format_number(sum_m) + " but Σ m_p = " + format_number(mass);
    return "";
}

std::uint64_t atomic_conflicts(const State& st) {
    const int nt = st.plan.threads;
    const std::int64_t np = static_cast<std::int64_t>(st.particles.size());
    std::vector<std::uint64_t> mask(st.grid.nodes(), 0);
    auto corners = [&](std::int64_t p) {
        return &st.grid.mesh.conn[4 * static_cast<std::size_t>(st.particles.elem[p])];
    };
    for (int t = 0; t < nt; ++t) {
        const Block b = static_block(np, t, nt);
        for (std::int64_t p = b.lo; p < b.hi; ++p)
            for (int i = 0; i < 4; ++i) mask[corners(p)[i]] |= 1ULL << (t % 64);
    }
    std::uint64_t n = 0;
    for (std::int64_t p = 0; p < np; ++p)
        for (int i = 0; i < 4; ++i) n += std::popcount(mask[corners(p)[i]]) > 1 ? 1 : 0;
    return n;
}

std::uint64_t footprint(const State& st) {
    const std::uint64_t ne = st.grid.elements(), nv = st.grid.nodes(), np = st.particles.size();
    return np * (8 * 18 + 8) + ne * (16 * 8 + 16 + 16 + 4) + nv * (sizeof(NodeState) + 24 + 1);
}

// Each particle's mass indexed by its id, after checking that the ids are a permutation of
// 0..n-1; `why` says what is wrong when they are not.
std::vector<double> masses_by_id(const Particles& p, std::string& why) {
    const std::size_t n = p.size();
    std::vector<double> mass(n, 0);
    std::vector<char> seen(n, 0);
    for (std::size_t i = 0; i < n; ++i) {
        const std::uint32_t id = p.id[i];
        if (id >= n || seen[id]) {
            why = "the particle ids are not a permutation of 0.." + std::to_string(n - 1) + " (id " +
                  std::to_string(id) + " at position " + std::to_string(i) + ")";
            return {};
        }
        seen[id] = 1;
        mass[id] = p.mass[i];
    }
    return mass;
}

}  // namespace suite::mpm
