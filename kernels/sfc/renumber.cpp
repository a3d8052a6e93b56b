// First-touch renumbering, in parallel. A serial loop would give vertex v the next number when
// the loop first meets it, i.e. number the vertices in the order of the corner position
// p = i * corners + j at which each is first met. Here:
//   1. each thread gathers its block of the old connectivity in the new element order,
//   2. first[v] = the smallest position at which v occurs (atomic min over all corners),
//   3. a bit is set at every such position (a scan over the vertices, not the corners),
//   4. prefix counts of the bit words give each position its rank among them,
//   5. new_id[v] = the rank of first[v], which is exactly the serial loop's number;
//   6. the connectivity and coordinates are rewritten.
// Only steps 2 and 6 touch every corner; the others walk the vertices or the bit words in order.
#include "kernels/sfc/renumber.hpp"

#include <omp.h>

#include <atomic>
#include <limits>
#include <vector>

#include "harness/kernel/blocks.hpp"

namespace suite::sfc {

namespace {

constexpr std::uint32_t unset = std::numeric_limits<std::uint32_t>::max();

// Steps 1 and 5 shared by both orders; `number` runs between them inside the parallel region.
template <class Number>
void rewrite(const mesh::MeshView& in, const std::uint32_t* perm, const std::uint32_t* new_id, const MeshOut& out,
             Number number) {
    const int k = in.dim + 1;
    const std::int64_t ne = static_cast<std::int64_t>(in.elements), nv = static_cast<std::int64_t>(in.vertices);
#pragma omp parallel
    {
        const Block eb = my_block(ne);
        for (std::int64_t i = eb.lo; i < eb.hi; ++i) {
            const std::uint32_t* c = in.conn + static_cast<std::size_t>(perm[i]) * k;
            for (int j = 0; j < k; ++j) out.conn[i * k + j] = c[j];
        }
        number(eb);  // ends with a barrier
        for (std::int64_t p = eb.lo * k; p < eb.hi * k; ++p) out.conn[p] = new_id[out.conn[p]];
        const Block vb = my_block(nv);
        for (std::int64_t v = vb.lo; v < vb.hi; ++v) {
            const std::uint32_t to = new_id[v];
            out.x[to] = in.x[v];
            out.y[to] = in.y[v];
            if (in.dim == 3) out.z[to] = in.z[v];
        }
    }
}

}  // namespace

void renumber_first_touch(const mesh::MeshView& in, const std::uint32_t* perm, std::uint32_t* new_id,
                          const RenumberScratch& sc, const MeshOut& out) {
    const int k = in.dim + 1;
    const std::int64_t nv = static_cast<std::int64_t>(in.vertices);
    const std::int64_t words = static_cast<std::int64_t>(rank_words(in.elements, k));
    const int threads = omp_get_max_threads();
    std::vector<std::uint64_t> touched(static_cast<std::size_t>(threads) + 1),
        untouched(static_cast<std::size_t>(threads) + 1);
    rewrite(in, perm, new_id, out, [&](const Block& eb) {
        const int t = omp_get_thread_num(), nt = omp_get_num_threads();
        const Block vb = my_block(nv), wb = my_block(words);
        for (std::int64_t v = vb.lo; v < vb.hi; ++v) sc.first[v] = unset;
        for (std::int64_t w = wb.lo; w < wb.hi; ++w) sc.bits[w] = 0;
#pragma omp barrier
        for (std::int64_t p = eb.lo * k; p < eb.hi * k; ++p) {
            std::atomic_ref<std::uint32_t> f(sc.first[out.conn[p]]);
            const auto pos = static_cast<std::uint32_t>(p);
            std::uint32_t seen = f.load(std::memory_order_relaxed);
            while (pos < seen && !f.compare_exchange_weak(seen, pos, std::memory_order_relaxed)) {
            }
        }
#pragma omp barrier
        std::uint64_t mine_untouched = 0;
        for (std::int64_t v = vb.lo; v < vb.hi; ++v) {
            const std::uint32_t p = sc.first[v];
            if (p == unset)
                ++mine_untouched;
            else
                std::atomic_ref<std::uint64_t>(sc.bits[p / 64]).fetch_or(1ULL << (p % 64), std::memory_order_relaxed);
        }
        untouched[t + 1] = mine_untouched;
#pragma omp barrier
        std::uint64_t mine = 0;
        for (std::int64_t w = wb.lo; w < wb.hi; ++w) {
            sc.rank[w] = static_cast<std::uint32_t>(mine);  // within this thread's words, for now
            mine += static_cast<std::uint64_t>(__builtin_popcountll(sc.bits[w]));
        }
        touched[t + 1] = mine;
#pragma omp barrier
#pragma omp single
        {
            for (int u = 0; u < nt; ++u) touched[u + 1] += touched[u];
            untouched[0] = touched[nt];  // untouched vertices are numbered after all touched ones
            for (int u = 0; u < nt; ++u) untouched[u + 1] += untouched[u];
        }
        for (std::int64_t w = wb.lo; w < wb.hi; ++w) sc.rank[w] += static_cast<std::uint32_t>(touched[t]);
#pragma omp barrier
        std::uint64_t next_untouched = untouched[t];
        for (std::int64_t v = vb.lo; v < vb.hi; ++v) {
            const std::uint32_t p = sc.first[v];
            if (p == unset)
                new_id[v] = static_cast<std::uint32_t>(next_untouched++);
            else
                new_id[v] = sc.rank[p / 64] + static_cast<std::uint32_t>(
                                                  __builtin_popcountll(sc.bits[p / 64] & ((1ULL << (p % 64)) - 1)));
        }
#pragma omp barrier
    });
}

void apply_vertex_order(const mesh::MeshView& in, const std::uint32_t* perm, const std::uint32_t* new_id,
                        const MeshOut& out) {
    rewrite(in, perm, new_id, out, [](const Block&) {
#pragma omp barrier
    });
}

}  // namespace suite::sfc
