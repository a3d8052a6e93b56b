// The pattern of a P1 triangle mesh, in one parallel region:
//   count   v2e_count[v] = triangles at v                 (triangle blocks, relaxed atomic adds)
//   scan    v2e_ptr = exclusive prefix sum of the counts
//   lists   v2e[v2e_ptr[v] ...] = the triangles at v       (triangle blocks, atomic slots)
//   rows    row_count[v] = distinct corners of those triangles (vertex blocks)
//   scan    row_ptr
//   fill    col[row_ptr[v] ...] = those corners, ascending (vertex blocks)
// The lists come out in any order; each row is sorted, so the pattern does not depend on it.
#include "kernels/fem/csr.hpp"

#include <omp.h>

#include <algorithm>
#include <atomic>
#include <vector>

#include "harness/kernel/blocks.hpp"

namespace suite::fem {

namespace {

// In-place exclusive prefix sum of a[0, n) by the whole team, a[n] = the total. `partial`
// holds one sum a thread; every thread adds the sums before its own in the same order.
void team_exclusive_scan(std::uint32_t* a, std::int64_t n, std::uint64_t* partial) {
    const int t = omp_get_thread_num(), nt = omp_get_num_threads();
    const Block b = static_block(n, t, nt);
    std::uint64_t sum = 0;
    for (std::int64_t i = b.lo; i < b.hi; ++i) sum += a[i];
    partial[t] = sum;
#pragma omp barrier
    std::uint64_t offset = 0, total = 0;
    for (int k = 0; k < nt; ++k) {
        if (k < t) offset += partial[k];
        total += partial[k];
    }
    for (std::int64_t i = b.lo; i < b.hi; ++i) {
        const std::uint32_t c = a[i];
        a[i] = static_cast<std::uint32_t>(offset);
        offset += c;
    }
    if (t == nt - 1) a[n] = static_cast<std::uint32_t>(total);
#pragma omp barrier
}

// The distinct corners of the triangles at v, ascending, into `row`.
void gather_row(const MeshArrays& m, const PatternScratch& s, std::int64_t v, std::vector<std::uint32_t>& row) {
    row.clear();
    for (std::uint32_t k = s.v2e_ptr[v]; k < s.v2e_ptr[v + 1]; ++k) {
        const std::uint32_t* c = m.conn + 3 * static_cast<std::int64_t>(s.v2e[k]);
        row.insert(row.end(), c, c + 3);
    }
    std::sort(row.begin(), row.end());
    row.erase(std::unique(row.begin(), row.end()), row.end());
}

}  // namespace

void build_pattern(const MeshArrays& m, Pattern& p, const PatternScratch& s) {
    p.n = m.nv;
#pragma omp parallel
    {
        const Block vb = my_block(m.nv), eb = my_block(m.ne);
        for (std::int64_t v = vb.lo; v < vb.hi; ++v) s.v2e_ptr[v] = 0;
#pragma omp barrier
        for (std::int64_t e = eb.lo; e < eb.hi; ++e)
            for (int j = 0; j < 3; ++j)
                std::atomic_ref<std::uint32_t>(s.v2e_ptr[m.conn[3 * e + j]]).fetch_add(1, std::memory_order_relaxed);
#pragma omp barrier
        team_exclusive_scan(s.v2e_ptr, m.nv, s.partial);
        for (std::int64_t v = vb.lo; v < vb.hi; ++v) s.fill[v] = s.v2e_ptr[v];
#pragma omp barrier
        for (std::int64_t e = eb.lo; e < eb.hi; ++e)
            for (int j = 0; j < 3; ++j) {
                const std::uint32_t slot =
                    std::atomic_ref<std::uint32_t>(s.fill[m.conn[3 * e + j]]).fetch_add(1, std::memory_order_relaxed);
                s.v2e[slot] = static_cast<std::uint32_t>(e);
            }
#pragma omp barrier
        std::vector<std::uint32_t> row;
        for (std::int64_t v = vb.lo; v < vb.hi; ++v) {
            gather_row(m, s, v, row);
            p.row_ptr[v] = static_cast<std::uint32_t>(row.size());
        }
#pragma omp barrier
        team_exclusive_scan(p.row_ptr, m.nv, s.partial);
        if (p.col)
            for (std::int64_t v = vb.lo; v < vb.hi; ++v) {
                gather_row(m, s, v, row);
                std::copy(row.begin(), row.end(), p.col + p.row_ptr[v]);
            }
    }
}

}  // namespace suite::fem
