// A simulation from its Setup: the grid loaded and ordered once, the particles seeded and put
// in their starting order; and the schedule of the reorderings between steps.
#include <algorithm>
#include <random>

#include "harness/common/units.hpp"
#include "harness/kernel/arena.hpp"
#include "kernels/mesh/mesh_spec.hpp"
#include "kernels/mpm/choices.hpp"
#include "kernels/mpm/mpm.hpp"
#include "kernels/sfc/encode.hpp"
#include "kernels/sfc/pipeline.hpp"

namespace suite::mpm {

namespace {

void shuffle_particles(State& st, std::uint64_t seed) {
    const std::size_t n = st.particles.size();
    std::vector<std::uint32_t> order(n);
    for (std::size_t i = 0; i < n; ++i) order[i] = static_cast<std::uint32_t>(i);
    std::mt19937_64 rng(seed);
    std::shuffle(order.begin(), order.end(), rng);
    reorder_particles(st, order);
}

}  // namespace

std::uint64_t state_bytes(const mesh::MeshCounts& c, std::uint64_t particles, int copies, bool implicit) {
    const std::uint64_t ne = c.elements, nv = c.vertices;
    const std::uint64_t grid = ne * (128 + 16 + 16 + 4 + 16) + nv * (64 + 25);
    std::uint64_t system = 0;
    if (implicit) {
        // The accelerations; the active system on at most every corner of the particles' elements:
        // 3 rows a node of 3 columns a neighbour (30 neighbours, itself included, bounds a
        // tetrahedral grid's; a box grid's have 15), 12 B an entry, 11 vectors of 3 doubles, the
        // block offsets of its elements (64 B) and the node pairs sorted while the pattern is built.
        const std::uint64_t nodes = std::min(nv, 4 * particles), elements = std::min(ne, particles);
        system = particles * 24 + nodes * (9 * 30 * 12 + 11 * 24 + 8) + elements * (64 + 16 * 8);
    }
    return static_cast<std::uint64_t>(copies) * (grid + particles * 160 + system) + ne * 40 + nv * 24 * 3;
}

std::uint64_t particles_bound(const mesh::MeshSpec& spec, const mesh::MeshCounts& c, const Settings& s) {
    const std::uint64_t all = c.elements * static_cast<std::uint64_t>(std::max(s.per_element, 0));
    if (spec.kind != mesh::MeshSpec::Kind::box) return all;
    // The region's share of the unit cube, widened by a layer of elements on every side (an
    // element belongs to the region by its centroid).
    const double per_axis = static_cast<double>(1ULL << spec.refine);  // each refinement halves an element
    const double cells[3] = {spec.nx * per_axis, spec.ny * per_axis, spec.nz * per_axis};
    double share = 1;
    for (int a = 0; a < 3; ++a) {
        const double lo = std::max(0.0, s.region.lo[a] - 1 / cells[a]),
                     hi = std::min(1.0, s.region.hi[a] + 1 / cells[a]);
        share *= std::max(0.0, hi - lo);
    }
    return std::min(all, static_cast<std::uint64_t>(share * static_cast<double>(all)) + 1);
}

State build(const Setup& s, Arena* arena) {
    grid_orderings().at(s.ordering);
    const ParticleOrder order = particle_orders().at(s.particles).what;
    if (s.sort_every < 0 && s.sort_every != sort_auto)
        throw UsageError("--sort-every=" + std::to_string(s.sort_every) +
                         ": auto or a whole number of steps >= 0 (0: sort at the start only)");
    if (s.sort_every == sort_auto && !(s.sort_threshold > 0 && s.sort_threshold <= 1e9))
        throw UsageError("--sort-threshold=" + format_number(s.sort_threshold) +
                         ": the decay a reordering costs, a number in (0, 1e9]");
    if (!(s.renumber_share >= 0 && s.renumber_share <= 1))
        throw UsageError("--renumber-share=" + format_number(s.renumber_share) +
                         ": the share of the particles outside the last renumbering's elements, a number in [0, 1]");
    const mesh::MeshSpec spec = mesh::parse_mesh_spec(s.mesh);
    const mesh::MeshCounts counts = mesh::mesh_counts(spec);
    if (counts.dim != 3)
        throw UsageError(
            "--mesh=" + s.mesh +
            ": the MPM background grid must be made of tetrahedra (e.g. box:NX,NY,NZ); this one has triangles");
    const std::uint64_t need = state_bytes(counts, particles_bound(spec, counts, s.settings), 1,
                                           s.settings.integrator != Integrator::explicit_step),
                        have = available_memory_bytes(MemoryPolicy{});
    if (need > have)
        throw UsageError("--mesh=" + s.mesh + " with " + std::to_string(s.settings.per_element) +
                         " particles per element needs about " + format_bytes(need) +
                         " for the grid and its particles, more than the " + format_bytes(have) +
                         " of memory available; use a smaller grid or fewer particles per element");
    mesh::Mesh m = mesh::load_mesh(spec);
    m = sfc::ordered(m, s.ordering, s.seed, sfc::max_depth(3));
    State st = make_state(make_grid(std::move(m)), s.settings, s.strategy, s.threads, s.force, arena);
    if (order.shuffle) shuffle_particles(st, s.seed);
    st.order.fresh = same_element_share(st.particles);
    if (order.sorts) reorder(st, s, ReorderCause::start);
    return st;
}

std::string sort_every_text(int sort_every) {
    return "--sort-every=" + (sort_every == sort_auto ? std::string("auto") : std::to_string(sort_every));
}

const char* reorder_cause_name(ReorderCause c) {
    switch (c) {
        case ReorderCause::none:
            return "";
        case ReorderCause::start:
            return "start";
        case ReorderCause::every:
            return "every";
        case ReorderCause::decayed:
            return "decayed";
    }
    return "";
}

void reorder(State& st, const Setup& s, ReorderCause cause) {
    OrderTracker& t = st.order;
    const double before = same_element_share(st.particles);
    const bool renumbers = particle_orders().at(s.particles).what.renumbers;
    double outside = 0;
    if (renumbers) {
        std::uint64_t out = 0;
        for (std::uint32_t e : st.particles.elem) out += e >= t.prefix ? 1 : 0;
        outside = st.particles.size() ? static_cast<double>(out) / static_cast<double>(st.particles.size()) : 0;
    }
    const bool renumber = renumbers && (cause != ReorderCause::decayed || outside >= s.renumber_share);
    if (renumber) {
        t.prefix = renumber_active(st);
        ++t.renumberings;
    }
    sort_particles(st);
    const double after = same_element_share(st.particles);
    if (t.log.size() < OrderTracker::log_limit)
        t.log.push_back({st.steps, cause, t.decay, before, after, outside, renumber});
    ++t.count;
    t.last_cause = cause;
    t.last_step = st.steps;
    t.fresh = after;
    t.decay = 0;
}

void advance(State& st, const Setup& s) {
    step(st);
    if (!st.implicit.failure.empty()) return;  // a failed implicit step changed nothing: no reordering either
    if (!particle_orders().at(s.particles).what.sorts) return;
    if (s.sort_every == sort_auto) {
        // The decay since the last reordering grows by how far below its fresh share the order is now.
        st.order.decay += std::max(0.0, st.order.fresh - same_element_share(st.particles));
        if (st.order.decay >= s.sort_threshold) reorder(st, s, ReorderCause::decayed);
        return;
    }
    if (s.sort_every > 0 && st.steps % static_cast<std::uint64_t>(s.sort_every) == 0)
        reorder(st, s, ReorderCause::every);
}

}  // namespace suite::mpm
