// A simulation from its Setup: the grid loaded and ordered once, the particles seeded and put
// in their starting order; and the schedule of the reorderings between steps.
#include <algorithm>
#include <random>

#include "harness/common/units.hpp"
#include "kernels/mesh/mesh_spec.hpp"
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

State build(const Setup& s) {
    const auto& names = {"natural", "random", "morton", "hilbert"};
    if (std::find(names.begin(), names.end(), s.ordering) == names.end())
        throw UsageError("unknown MPM grid ordering '" + s.ordering + "'; orderings: " + orderings_accepted);
    if (s.particles != "unsorted" && s.particles != "sorted" && s.particles != "dynamic")
        throw UsageError("unknown particle order '" + s.particles + "'; particle orders: " + particle_orders_accepted);
    if (s.sort_every < 0) throw UsageError("--sort-every=" + std::to_string(s.sort_every) + ": a whole number of steps >= 0 (0: sort at the start only)");
    mesh::Mesh m = mesh::load_mesh(mesh::parse_mesh_spec(s.mesh));
    if (m.dim != 3)
        throw UsageError("--mesh=" + s.mesh + ": the MPM background grid must be made of tetrahedra (e.g. box:NX,NY,NZ); this one has triangles");
    m = sfc::ordered(m, s.ordering, s.seed, sfc::max_depth(3));
    State st = make_state(make_grid(std::move(m)), s.settings, s.strategy, s.threads, s.force);
    if (s.particles == "unsorted") shuffle_particles(st, s.seed);
    else {
        if (s.particles == "dynamic") renumber_active(st);
        sort_particles(st);
    }
    return st;
}

bool reorders_after(const Setup& s, std::uint64_t step) {
    return s.particles != "unsorted" && s.sort_every > 0 && step % static_cast<std::uint64_t>(s.sort_every) == 0;
}

void advance(State& st, const Setup& s) {
    step(st);
    if (!reorders_after(s, st.steps)) return;
    if (s.particles == "dynamic") renumber_active(st);
    sort_particles(st);
}

}  // namespace suite::mpm
