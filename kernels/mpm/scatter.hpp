#pragma once
// The particle-to-node scatter shared by P2G and the velocity scatter: for every particle and
// each corner i of its element, Width values c[i][k] added to the node's doubles Offset + k
// (NodeState as doubles: m = 0, p = 1..3, f = 4..6). How the threads avoid racing on a node is
// the state's ScatterPlan (mpm.hpp). Called outside any parallel region; opens its own.
#include <omp.h>

#include <atomic>
#include <cmath>
#include <cstdint>

#include "harness/kernel/blocks.hpp"
#include "kernels/mpm/mpm.hpp"

namespace suite::mpm {

inline double* node_doubles(Array<NodeState>& nodes, std::uint32_t n) { return &nodes[n].m; }

// The colour and partition strategies (scatter_strategies.cpp), on per-particle callbacks
// through a plain function pointer so that the strategies are compiled once.
using ContributionFn = void (*)(const State& st, std::size_t p, double* c, void* ctx);
void scatter_colour(State& st, int offset, int width, ContributionFn fn, void* ctx);
void scatter_partition(State& st, int offset, int width, ContributionFn fn, void* ctx);

// Mixed integration (mpm.hpp, Integration): Σ V_p of each element's particles into
// st.element_volume (0 for an empty element).
void sum_element_volumes(State& st);

// The factor mixed integration puts on the volumes of element e's particles: |e| / Σ V_p when e
// and its face neighbours (or the walls in their place) hold particles, else 1. |e| from the
// shape functions: the gradients of λ1..λ3 are the rows of J⁻¹, so |e| = 1 / (6 |det|).
inline double volume_scale(std::uint32_t e, const double* shape, const std::int32_t* nb, const double* sum) {
    for (int i = 0; i < 4; ++i) {
        const std::int32_t n = nb[4 * static_cast<std::size_t>(e) + i];
        if (n >= 0 && !(sum[n] > 0)) return 1;
    }
    const double* s = shape + 16 * static_cast<std::size_t>(e);
    const double det = s[5] * (s[10] * s[15] - s[11] * s[14]) - s[6] * (s[9] * s[15] - s[11] * s[13]) +
                       s[7] * (s[9] * s[14] - s[10] * s[13]);
    return 1 / (6 * std::fabs(det) * sum[e]);
}

template <int Offset, int Width, class Contribution>
void scatter(State& st, const Contribution& contribution) {
    const std::uint32_t* const conn = st.grid.mesh.conn.data();
    const std::uint32_t* const elem = st.particles.elem.data();
    const std::int64_t np = static_cast<std::int64_t>(st.particles.size());
    switch (st.plan.strategy) {
        case Strategy::serial: {
            for (std::int64_t p = 0; p < np; ++p) {
                double c[4 * Width];
                contribution(static_cast<std::size_t>(p), c);
                const std::uint32_t* corners = conn + 4 * static_cast<std::size_t>(elem[p]);
                for (int i = 0; i < 4; ++i) {
                    double* d = node_doubles(st.nodes, corners[i]) + Offset;
                    for (int k = 0; k < Width; ++k) d[k] += c[Width * i + k];
                }
            }
            return;
        }
        case Strategy::atomic: {
#pragma omp parallel
            {
                const Block b = my_block(np);
                for (std::int64_t p = b.lo; p < b.hi; ++p) {
                    double c[4 * Width];
                    contribution(static_cast<std::size_t>(p), c);
                    const std::uint32_t* corners = conn + 4 * static_cast<std::size_t>(elem[p]);
                    for (int i = 0; i < 4; ++i) {
                        double* d = node_doubles(st.nodes, corners[i]) + Offset;
                        for (int k = 0; k < Width; ++k)
                            std::atomic_ref<double>(d[k]).fetch_add(c[Width * i + k], std::memory_order_relaxed);
                    }
                }
            }
            return;
        }
        case Strategy::colour:
        case Strategy::partition: {
            auto fn = [](const State& s, std::size_t p, double* c, void* ctx) {
                (*static_cast<const Contribution*>(ctx))(p, c);
                (void)s;
            };
            void* ctx = const_cast<void*>(static_cast<const void*>(&contribution));
            if (st.plan.strategy == Strategy::colour)
                scatter_colour(st, Offset, Width, fn, ctx);
            else
                scatter_partition(st, Offset, Width, fn, ctx);
            return;
        }
    }
}

}  // namespace suite::mpm
