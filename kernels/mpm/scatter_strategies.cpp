// The two scatter strategies that avoid atomics (mpm.hpp, Strategy):
//   colour     greedy colouring of the elements by shared nodes, once per grid; in a scatter,
//              one colour at a time, its elements split over the threads, each element's
//              particles (through the bins) added straight into its nodes.
//   partition  per scatter, the elements cut into one contiguous run per thread holding about
//              the same number of particles; a node whose elements lie in two runs is shared:
//              its additions go into the thread's slot and are summed afterwards.
#include <omp.h>

#include <algorithm>
#include <atomic>
#include <bit>
#include <stdexcept>

#include "harness/kernel/blocks.hpp"
#include "kernels/mpm/scatter.hpp"

namespace suite::mpm {

void plan_colours(const Grid& g, ScatterPlan& plan) {
    const std::size_t ne = g.elements();
    std::vector<std::uint64_t> used(g.nodes(), 0);  // per node, the colours of its elements so far
    std::vector<std::uint8_t> colour(ne);
    int colours = 0;
    for (std::size_t e = 0; e < ne; ++e) {
        const std::uint32_t* c = &g.mesh.conn[4 * e];
        const std::uint64_t taken = used[c[0]] | used[c[1]] | used[c[2]] | used[c[3]];
        if (taken == ~0ULL) throw std::runtime_error("MPM colouring: an element's nodes already use 64 colours");
        const int k = std::countr_one(taken);
        colour[e] = static_cast<std::uint8_t>(k);
        for (int i = 0; i < 4; ++i) used[c[i]] |= 1ULL << k;
        colours = std::max(colours, k + 1);
    }
    plan.colour_start.assign(static_cast<std::size_t>(colours) + 1, 0);
    for (std::size_t e = 0; e < ne; ++e) ++plan.colour_start[colour[e] + 1u];
    for (int k = 0; k < colours; ++k) plan.colour_start[k + 1] += plan.colour_start[k];
    plan.colour_elems.resize(ne);
    std::vector<std::uint32_t> next(plan.colour_start.begin(), plan.colour_start.end() - 1);
    for (std::size_t e = 0; e < ne; ++e) plan.colour_elems[next[colour[e]]++] = static_cast<std::uint32_t>(e);
}

void plan_partition(const Grid& g, ScatterPlan& plan) {
    if (plan.threads > 64)
        throw std::runtime_error("MPM partition strategy: at most 64 threads (one bit each per node)");
    plan.touched.assign(g.nodes(), 0);
    plan.slot.assign(g.nodes(), -1);
    plan.run_start.assign(static_cast<std::size_t>(plan.threads) + 1, 0);
}

void scatter_colour(State& st, int offset, int width, ContributionFn fn, void* ctx) {
    const ScatterPlan& plan = st.plan;
    const std::uint32_t* const conn = st.grid.mesh.conn.data();
    const Bins& bins = st.bins;
#pragma omp parallel
    {
        double c[4 * 7];
        for (int k = 0; k < plan.colours(); ++k) {
            const std::int64_t lo = plan.colour_start[k], n = plan.colour_start[k + 1] - lo;
            const Block b = my_block(n);
            for (std::int64_t j = lo + b.lo; j < lo + b.hi; ++j) {
                const std::uint32_t e = plan.colour_elems[j];
                const std::uint32_t* corners = conn + 4 * static_cast<std::size_t>(e);
                for (std::uint32_t q = bins.start[e]; q < bins.start[e + 1]; ++q) {
                    fn(st, bins.order[q], c, ctx);
                    for (int i = 0; i < 4; ++i) {
                        double* d = node_doubles(st.nodes, corners[i]) + offset;
                        for (int v = 0; v < width; ++v) d[v] += c[width * i + v];
                    }
                }
            }
#pragma omp barrier
        }
    }
    st.plan.synchronised = 0;
}

void scatter_partition(State& st, int offset, int width, ContributionFn fn, void* ctx) {
    ScatterPlan& plan = st.plan;
    const std::uint32_t* const conn = st.grid.mesh.conn.data();
    const Bins& bins = st.bins;
    const std::size_t ne = st.grid.elements();
    const std::int64_t nn = st.node_hi;
    const std::uint64_t np = st.particles.size();
    std::uint64_t synchronised = 0;
    std::uint32_t shared_count = 0;
#pragma omp parallel reduction(+ : synchronised)
    {
        const int t = omp_get_thread_num(), nt = omp_get_num_threads();
#pragma omp single
        {
            // Runs balanced by particles: thread t starts at the first element whose particles
            // begin at or after t/nt of them.
            plan.run_start.assign(static_cast<std::size_t>(nt) + 1, static_cast<std::uint32_t>(ne));
            for (int k = 0; k < nt; ++k) {
                const std::uint64_t goal = np * static_cast<std::uint64_t>(k) / static_cast<std::uint64_t>(nt);
                plan.run_start[k] = static_cast<std::uint32_t>(
                    std::lower_bound(bins.start.begin(), bins.start.end() - 1, goal) - bins.start.begin());
            }
            plan.run_start[0] = 0;
        }
        const Block nb = my_block(nn);
        for (std::int64_t n = nb.lo; n < nb.hi; ++n) plan.touched[n] = 0;
#pragma omp barrier
        const std::uint32_t lo = plan.run_start[t], hi = plan.run_start[t + 1];
        for (std::uint32_t e = lo; e < hi; ++e)
            if (bins.start[e] != bins.start[e + 1])
                for (int i = 0; i < 4; ++i) {
                    std::uint64_t& mask = plan.touched[conn[4 * static_cast<std::size_t>(e) + i]];
                    if (!(mask & (1ULL << t)))
                        std::atomic_ref<std::uint64_t>(mask).fetch_or(1ULL << t, std::memory_order_relaxed);
                }
#pragma omp barrier
#pragma omp single
        {
            // Slots for the shared nodes, in node order.
            std::uint32_t s = 0;
            plan.shared.clear();
            for (std::int64_t n = 0; n < nn; ++n)
                if (std::popcount(plan.touched[n]) > 1) {
                    plan.slot[n] = static_cast<std::int32_t>(s++);
                    plan.shared.push_back(static_cast<std::uint32_t>(n));
                }
            shared_count = s;
            const std::size_t need = static_cast<std::size_t>(nt) * s;
            if (plan.slots.size() < need) plan.slots.resize(need);
        }
        NodeState* mine = plan.slots.data() + static_cast<std::size_t>(t) * shared_count;
        for (std::uint32_t k = 0; k < shared_count; ++k) mine[k] = NodeState{};
        double c[4 * 7];
        for (std::uint32_t e = lo; e < hi; ++e) {
            const std::uint32_t* corners = conn + 4 * static_cast<std::size_t>(e);
            for (std::uint32_t q = bins.start[e]; q < bins.start[e + 1]; ++q) {
                fn(st, bins.order[q], c, ctx);
                for (int i = 0; i < 4; ++i) {
                    const std::uint32_t n = corners[i];
                    const bool shared = std::popcount(plan.touched[n]) > 1;
                    double* d = shared ? &mine[plan.slot[n]].m + offset : node_doubles(st.nodes, n) + offset;
                    for (int v = 0; v < width; ++v) d[v] += c[width * i + v];
                    synchronised += shared ? 1 : 0;
                }
            }
        }
#pragma omp barrier
        const Block sb = my_block(shared_count);
        for (std::int64_t k = sb.lo; k < sb.hi; ++k) {
            double* d = node_doubles(st.nodes, plan.shared[k]) + offset;
            for (int u = 0; u < nt; ++u) {
                const double* from = &plan.slots[static_cast<std::size_t>(u) * shared_count + k].m + offset;
                for (int v = 0; v < width; ++v) d[v] += from[v];
            }
            plan.slot[plan.shared[k]] = -1;
        }
    }
    plan.synchronised = synchronised;
    plan.shared_nodes = shared_count;
}

}  // namespace suite::mpm
