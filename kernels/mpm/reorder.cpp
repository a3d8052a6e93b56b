// Reordering during a simulation: the particles sorted along the curve, and the grid renumbered
// so that the elements holding particles (and their nodes) come first, in curve order.
#include <algorithm>
#include <cstring>
#include <numeric>

#include "harness/kernel/blocks.hpp"
#include "kernels/mpm/mpm.hpp"
#include "kernels/sfc/pipeline.hpp"

namespace suite::mpm {

namespace {

// Own memory: the gathered values in a new vector, which takes the array's place (V: a
// std::vector or an Array that owns its storage).
template <class V, class T = typename V::value_type>
void gather(V& v, const std::vector<std::uint32_t>& order, std::size_t width, std::vector<T>& scratch) {
    scratch.resize(v.size());
    const std::int64_t n = static_cast<std::int64_t>(order.size());
#pragma omp parallel for schedule(static)
    for (std::int64_t i = 0; i < n; ++i)
        for (std::size_t k = 0; k < width; ++k)
            scratch[width * static_cast<std::size_t>(i) + k] = v[width * order[i] + k];
    v.swap(scratch);
}

// Placed memory, inside a parallel region: this thread's block [b.lo, b.hi) of the result
// gathered into its own part of the scratch (`mine`, 32 B per particle of the block, first
// touched by this thread), then, once every thread has read the array, copied back into the
// same block of it, so that no page of the array changes hands. The next array's gather may
// start at once: it writes only this thread's part of the scratch, and reads an array nobody
// writes before the next barrier.
template <class T>
void gather_back(T* v, const std::uint32_t* order, std::size_t width, Block b, void* mine) {
    // Bytes, not T: the scratch serves arrays of several types (memcpy keeps that defined).
    unsigned char* const s = static_cast<unsigned char*>(mine);
    const std::size_t row = width * sizeof(T);
    for (std::int64_t i = b.lo; i < b.hi; ++i)
        std::memcpy(s + row * static_cast<std::size_t>(i - b.lo), v + width * order[i], row);
#pragma omp barrier
    std::memcpy(v + width * static_cast<std::size_t>(b.lo), s,
                width * static_cast<std::size_t>(b.hi - b.lo) * sizeof(T));
}

}  // namespace

void sort_particles(State& st) {
    Particles& pt = st.particles;
    const std::size_t np = pt.size(), ne = st.grid.elements();
    // Counting sort by element number: stable, O(particles + elements). The grid's own order, not
    // the Hilbert curve's: on a natural grid, particles sorted along the curve read the elements'
    // shape functions and neighbours out of their memory order, and ran 12 % slower than seeded
    // ones in the same order of elements (the elastic collapse on box:24, locate 43 % and P2G 16 %
    // more time; mpm.md). On a curve-ordered grid the two orders are one.
    std::vector<std::uint32_t> start(ne + 1, 0), order(np);
    for (std::size_t p = 0; p < np; ++p) ++start[pt.elem[p] + 1];
    for (std::size_t r = 0; r < ne; ++r) start[r + 1] += start[r];
    for (std::size_t p = 0; p < np; ++p) order[start[pt.elem[p]]++] = static_cast<std::uint32_t>(p);
    reorder_particles(st, order);
}

void reorder_particles(State& st, const std::vector<std::uint32_t>& order) {
    Particles& pt = st.particles;
    if (pt.placed()) {
        const std::int64_t n = static_cast<std::int64_t>(pt.size());
        double* const d[] = {pt.x.data(),         pt.y.data(),         pt.z.data(),         pt.vx.data(),
                             pt.vy.data(),        pt.vz.data(),        pt.mass.data(),      pt.volume.data(),
                             pt.stress[0].data(), pt.stress[1].data(), pt.stress[2].data(), pt.stress[3].data(),
                             pt.stress[4].data(), pt.stress[5].data()};
        double* const w = pt.w.data();
        std::uint32_t* const u[] = {pt.elem.data(), pt.id.data()};
        double* const scratch = pt.scratch.buf.data();
        const std::uint32_t* const o = order.data();
#pragma omp parallel
        {
            const Block b = my_block(n);
            void* const mine = scratch + 4 * b.lo;
            for (double* v : d) gather_back(v, o, 1, b, mine);
            gather_back(w, o, 4, b, mine);
            for (std::uint32_t* v : u) gather_back(v, o, 1, b, mine);
            for (auto& acc : pt.accel)
                if (acc.size() == static_cast<std::size_t>(n)) gather_back(acc.data(), o, 1, b, mine);
        }
        bin_particles(st);
        return;
    }
    std::vector<double> scratch;
    for (auto* v : {&pt.x, &pt.y, &pt.z, &pt.vx, &pt.vy, &pt.vz, &pt.mass, &pt.volume}) gather(*v, order, 1, scratch);
    for (auto& s : pt.stress) gather(s, order, 1, scratch);
    for (auto& acc : pt.accel)
        if (acc.size() == pt.size()) gather(acc, order, 1, scratch);
    gather(pt.w, order, 4, scratch);
    std::vector<std::uint32_t> iscratch;
    gather(pt.elem, order, 1, iscratch);
    gather(pt.id, order, 1, iscratch);
    bin_particles(st);
}

void permute(State& st, const std::vector<std::uint32_t>& perm, const std::vector<std::uint32_t>& new_id) {
    // The implicit system's pattern names elements and nodes by number: built anew at the next
    // step (the active elements' numbers alone may come out the same after a renumbering).
    st.system.elements.clear();
    st.system.index.clear();
    Grid& g = st.grid;
    const std::size_t ne = g.elements(), nv = g.nodes();
    std::vector<std::uint32_t> new_elem(ne);
    for (std::size_t i = 0; i < ne; ++i) new_elem[perm[i]] = static_cast<std::uint32_t>(i);
    g.mesh = sfc::permuted(g.mesh, perm, new_id);
    std::vector<double> shape;
    gather(g.shape, perm, 16, shape);
    std::vector<std::int32_t> nb(4 * ne);
#pragma omp parallel for schedule(static)
    for (std::size_t i = 0; i < ne; ++i)
        for (int k = 0; k < 4; ++k) {
            const std::int32_t old = g.neighbour[4 * static_cast<std::size_t>(perm[i]) + k];
            nb[4 * i + k] = old < 0 ? -1 : static_cast<std::int32_t>(new_elem[static_cast<std::size_t>(old)]);
        }
    g.neighbour.swap(nb);
    std::vector<std::uint32_t> curve;
    gather(g.curve, perm, 1, curve);
    std::vector<std::uint8_t> wall(nv);
    for (std::size_t v = 0; v < nv; ++v) wall[new_id[v]] = g.wall[v];
    g.wall.swap(wall);
    for (auto& e : st.particles.elem) e = new_elem[e];
    st.plan = plan_scatter(g, st.plan.strategy, st.plan.threads);
    locate(st);
}

std::uint32_t renumber_active(State& st) {
    const Grid& g = st.grid;
    const std::size_t ne = g.elements(), nv = g.nodes();
    std::vector<char> active(ne, 0);
    for (std::uint32_t e : st.particles.elem) active[e] = 1;
    std::vector<std::uint32_t> perm;
    perm.reserve(ne);
    for (std::size_t e = 0; e < ne; ++e)
        if (active[e]) perm.push_back(static_cast<std::uint32_t>(e));
    std::sort(perm.begin(), perm.end(), [&](std::uint32_t a, std::uint32_t b) { return g.curve[a] < g.curve[b]; });
    const auto held = static_cast<std::uint32_t>(perm.size());
    for (std::size_t e = 0; e < ne; ++e)
        if (!active[e]) perm.push_back(static_cast<std::uint32_t>(e));
    // Nodes by first touch along the new element order.
    constexpr std::uint32_t none = ~0u;
    std::vector<std::uint32_t> new_id(nv, none);
    std::uint32_t next = 0;
    for (std::uint32_t e : perm)
        for (int k = 0; k < 4; ++k) {
            std::uint32_t& id = new_id[g.mesh.conn[4 * static_cast<std::size_t>(e) + k]];
            if (id == none) id = next++;
        }
    for (auto& id : new_id)
        if (id == none) id = next++;
    permute(st, perm, new_id);
    return held;
}

}  // namespace suite::mpm
