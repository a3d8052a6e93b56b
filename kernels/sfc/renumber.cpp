// First-touch renumbering, in parallel. A serial loop would give vertex v the next number when
// the loop first meets it; here each thread walks its block of corner positions and
//   1. gathers the old corner numbers into the output connectivity (conn[perm[i]]),
//   2. records in first[v] the smallest position at which v occurs (atomic min),
//   3. counts the positions that are some vertex's first; a prefix sum over threads gives each
//      thread the first number it hands out,
//   4. hands out numbers at those positions in order, which is exactly the serial order,
//   5. replaces the old numbers by new ones and moves the coordinates.
#include "kernels/sfc/renumber.hpp"

#include <omp.h>

#include <atomic>
#include <limits>
#include <vector>

#include "stream/stream_kernel.hpp"

namespace suite::sfc {

namespace {

constexpr std::uint32_t unset = std::numeric_limits<std::uint32_t>::max();

// Steps 1 and 5 shared by both orders; `number` runs between them inside the parallel region.
template <class Number>
void rewrite(const mesh::MeshView& in, const std::uint32_t* perm, const std::uint32_t* new_id, const MeshOut& out, Number number) {
    const int k = in.dim + 1;
    const std::int64_t ne = static_cast<std::int64_t>(in.elements), nv = static_cast<std::int64_t>(in.vertices);
#pragma omp parallel
    {
        const stream::Block eb = stream::my_block(ne);
        for (std::int64_t i = eb.lo; i < eb.hi; ++i) {
            const std::uint32_t* c = in.conn + static_cast<std::size_t>(perm[i]) * k;
            for (int j = 0; j < k; ++j) out.conn[i * k + j] = c[j];
        }
        number(eb);  // ends with a barrier
        for (std::int64_t p = eb.lo * k; p < eb.hi * k; ++p) out.conn[p] = new_id[out.conn[p]];
        const stream::Block vb = stream::my_block(nv);
        for (std::int64_t v = vb.lo; v < vb.hi; ++v) {
            const std::uint32_t to = new_id[v];
            out.x[to] = in.x[v];
            out.y[to] = in.y[v];
            if (in.dim == 3) out.z[to] = in.z[v];
        }
    }
}

}  // namespace

void renumber_first_touch(const mesh::MeshView& in, const std::uint32_t* perm, std::uint32_t* new_id, std::uint32_t* first, const MeshOut& out) {
    const int k = in.dim + 1;
    const std::int64_t nv = static_cast<std::int64_t>(in.vertices);
    const int threads = omp_get_max_threads();
    std::vector<std::uint64_t> touched(static_cast<std::size_t>(threads) + 1), untouched(static_cast<std::size_t>(threads) + 1);
    rewrite(in, perm, new_id, out, [&](const stream::Block& eb) {
        const int t = omp_get_thread_num(), nt = omp_get_num_threads();
        const stream::Block vb = stream::my_block(nv);
        for (std::int64_t v = vb.lo; v < vb.hi; ++v) first[v] = unset;
#pragma omp barrier
        const std::int64_t p0 = eb.lo * k, p1 = eb.hi * k;
        for (std::int64_t p = p0; p < p1; ++p) {
            std::atomic_ref<std::uint32_t> f(first[out.conn[p]]);
            const auto pos = static_cast<std::uint32_t>(p);
            std::uint32_t seen = f.load(std::memory_order_relaxed);
            while (pos < seen && !f.compare_exchange_weak(seen, pos, std::memory_order_relaxed)) {
            }
        }
#pragma omp barrier
        std::uint64_t mine = 0, mine_untouched = 0;
        for (std::int64_t p = p0; p < p1; ++p) mine += first[out.conn[p]] == static_cast<std::uint32_t>(p);
        for (std::int64_t v = vb.lo; v < vb.hi; ++v) mine_untouched += first[v] == unset;
        touched[t + 1] = mine;
        untouched[t + 1] = mine_untouched;
#pragma omp barrier
#pragma omp single
        {
            for (int u = 0; u < nt; ++u) touched[u + 1] += touched[u];
            untouched[0] = touched[nt];  // untouched vertices are numbered after all touched ones
            for (int u = 0; u < nt; ++u) untouched[u + 1] += untouched[u];
        }
        std::uint64_t next = touched[t];
        for (std::int64_t p = p0; p < p1; ++p) {
            const std::uint32_t v = out.conn[p];
            if (first[v] == static_cast<std::uint32_t>(p)) new_id[v] = static_cast<std::uint32_t>(next++);
        }
        std::uint64_t next_untouched = untouched[t];
        for (std::int64_t v = vb.lo; v < vb.hi; ++v)
            if (first[v] == unset) new_id[v] = static_cast<std::uint32_t>(next_untouched++);
#pragma omp barrier
    });
}

void apply_vertex_order(const mesh::MeshView& in, const std::uint32_t* perm, const std::uint32_t* new_id, const MeshOut& out) {
    rewrite(in, perm, new_id, out, [](const stream::Block&) {
#pragma omp barrier
    });
}

}  // namespace suite::sfc
