// Finding each particle's element: a walk from the element it was in, through the face opposite
// the corner whose shape function is most negative, until all four are >= 0 (to rounding).
// Then the bins (particles grouped by element) for the strategies that need them.
#include <algorithm>
#include <stdexcept>
#include <string>

#include "kernels/mpm/mpm.hpp"

namespace suite::mpm {

namespace {

constexpr double inside = -1e-12;  // a shape function this negative still counts as inside
constexpr int greedy_steps = 64;   // then the walk picks among the negative faces at random
constexpr int max_steps = 100000;

inline void barycentric(const double* s, double x, double y, double z, double* w) {
    for (int i = 0; i < 4; ++i) w[i] = s[4 * i] + s[4 * i + 1] * x + s[4 * i + 2] * y + s[4 * i + 3] * z;
}

}  // namespace

void locate(State& st) {
    Particles& pt = st.particles;
    const double* const shape = st.grid.shape.data();
    const std::int32_t* const nb = st.grid.neighbour.data();
    const std::uint32_t* const conn = st.grid.mesh.conn.data();
    const std::int64_t np = static_cast<std::int64_t>(pt.size());
    std::uint32_t node_hi = 0;
    bool lost = false;
#pragma omp parallel for schedule(static) reduction(max : node_hi) reduction(|| : lost)
    for (std::int64_t p = 0; p < np; ++p) {
        std::uint32_t e = pt.elem[p];
        double* w = &pt.w[4 * static_cast<std::size_t>(p)];
        std::uint64_t rng = 0x9e3779b97f4a7c15ULL * static_cast<std::uint64_t>(p + 1);
        for (int stepno = 0;; ++stepno) {
            barycentric(shape + 16 * static_cast<std::size_t>(e), pt.x[p], pt.y[p], pt.z[p], w);
            int worst = 0;
            for (int i = 1; i < 4; ++i)
                if (w[i] < w[worst]) worst = i;
            if (w[worst] >= inside) break;
            // The greedy walk can cycle in a mesh that is not Delaunay: after a while, a random
            // face among those the point lies beyond.
            if (stepno >= greedy_steps) {
                rng ^= rng << 13;
                rng ^= rng >> 7;
                rng ^= rng << 17;
                int neg[4], k = 0;
                for (int i = 0; i < 4; ++i)
                    if (w[i] < inside && nb[4 * static_cast<std::size_t>(e) + i] >= 0) neg[k++] = i;
                if (k > 0) worst = neg[rng % static_cast<std::uint64_t>(k)];
            }
            const std::int32_t next = nb[4 * static_cast<std::size_t>(e) + worst];
            // Beyond a boundary face: the position is on the wall (g2p keeps it in the box),
            // so this is rounding; the element stands.
            if (next < 0 || stepno >= max_steps) {
                lost = lost || stepno >= max_steps;
                break;
            }
            e = static_cast<std::uint32_t>(next);
        }
        // Rounding may leave a weight a hair below 0 or the sum a hair off 1: the weights are
        // clipped and renormalised, so that Σ w = 1 holds to rounding (mass is conserved).
        double sum = 0;
        for (int i = 0; i < 4; ++i) {
            w[i] = std::max(w[i], 0.0);
            sum += w[i];
        }
        for (int i = 0; i < 4; ++i) w[i] /= sum;
        pt.elem[p] = e;
        const std::uint32_t* c = conn + 4 * static_cast<std::size_t>(e);
        node_hi = std::max({node_hi, c[0] + 1, c[1] + 1, c[2] + 1, c[3] + 1});
    }
    if (lost) throw std::runtime_error("MPM: a particle's walk through the grid did not end (a broken mesh?)");
    st.node_hi = node_hi;
    bin_particles(st);
}

void bin_particles(State& st) {
    if (st.plan.strategy != Strategy::colour && st.plan.strategy != Strategy::partition) return;
    // Counting sort of the particles by element; stable, so a sorted particle order stays the
    // bins' order.
    const Particles& pt = st.particles;
    const std::int64_t np = static_cast<std::int64_t>(pt.size());
    Bins& b = st.bins;
    const std::size_t ne = st.grid.elements();
    b.start.assign(ne + 1, 0);
    b.order.resize(pt.size());
    for (std::int64_t p = 0; p < np; ++p) ++b.start[pt.elem[p] + 1];
    for (std::size_t e = 0; e < ne; ++e) b.start[e + 1] += b.start[e];
    b.next.assign(b.start.begin(), b.start.end() - 1);
    std::vector<std::uint32_t>& next = b.next;
    for (std::int64_t p = 0; p < np; ++p) b.order[next[pt.elem[p]]++] = static_cast<std::uint32_t>(p);
}

}  // namespace suite::mpm
