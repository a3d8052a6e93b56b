#include "kernels/mesh/edges.hpp"

#include <algorithm>
#include <atomic>

namespace suite::mesh {

EdgeTable build_edges(const MeshView& m) {
    const std::int64_t ne = static_cast<std::int64_t>(m.elements);
    const std::size_t nv = m.vertices;
    const int k = m.dim + 1, ec = edge_count(m.dim);
    const auto* pairs = local_edges(m.dim);
    // Every element's edges, each under its lower vertex (duplicates included) ...
    std::vector<std::uint64_t> start(nv + 1, 0);
#pragma omp parallel for schedule(static)
    for (std::int64_t e = 0; e < ne; ++e) {
        const std::uint32_t* c = m.conn + e * k;
        for (int j = 0; j < ec; ++j)
            std::atomic_ref<std::uint64_t>(start[std::min(c[pairs[j][0]], c[pairs[j][1]])])
                .fetch_add(1, std::memory_order_relaxed);
    }
    std::uint64_t sum = 0;
    for (std::size_t v = 0; v <= nv; ++v) {
        const std::uint64_t c = start[v];
        start[v] = sum;
        sum += c;
    }
    std::vector<std::uint32_t> all(sum);
    {
        std::vector<std::uint64_t> cursor(start.begin(), start.end() - 1);
#pragma omp parallel for schedule(static)
        for (std::int64_t e = 0; e < ne; ++e) {
            const std::uint32_t* c = m.conn + e * k;
            for (int j = 0; j < ec; ++j) {
                const std::uint32_t a = c[pairs[j][0]], b = c[pairs[j][1]];
                all[std::atomic_ref<std::uint64_t>(cursor[std::min(a, b)]).fetch_add(1, std::memory_order_relaxed)] =
                    std::max(a, b);
            }
        }
    }
    // ... then each row sorted and made unique, which also undoes the order the threads wrote in.
    EdgeTable t;
    t.row.assign(nv + 1, 0);
    const std::int64_t nvi = static_cast<std::int64_t>(nv);
#pragma omp parallel for schedule(dynamic, 4096)
    for (std::int64_t v = 0; v < nvi; ++v) {
        auto* b = all.data() + start[v];
        auto* e = all.data() + start[v + 1];
        std::sort(b, e);
        t.row[v + 1] = static_cast<std::uint64_t>(std::unique(b, e) - b);
    }
    for (std::size_t v = 0; v < nv; ++v) t.row[v + 1] += t.row[v];
    t.upper.resize(t.row[nv]);
#pragma omp parallel for schedule(static)
    for (std::int64_t v = 0; v < nvi; ++v)
        std::copy_n(all.data() + start[v], t.row[v + 1] - t.row[v], t.upper.data() + t.row[v]);
    return t;
}

}  // namespace suite::mesh
