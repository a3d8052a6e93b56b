#include "kernels/sfc/quality.hpp"

#include <algorithm>
#include <limits>

#include "harness/kernel/blocks.hpp"
#include "kernels/mesh/edges.hpp"

namespace suite::sfc {

OrderingQuality ordering_quality(const mesh::Mesh& m) {
    OrderingQuality q;
    const std::size_t nv = m.vertices(), ne = m.elements();
    const mesh::EdgeTable edges = mesh::build_edges(m.view());
    // Row i's leftmost entry: i itself (the diagonal) or its smallest neighbour.
    std::vector<std::uint32_t> leftmost(nv);
    for (std::size_t v = 0; v < nv; ++v) leftmost[v] = static_cast<std::uint32_t>(v);
    for (std::size_t a = 0; a < nv; ++a)
        for (std::uint64_t k = edges.row[a]; k < edges.row[a + 1]; ++k) {
            const std::uint32_t b = edges.upper[k];  // a < b
            q.bandwidth = std::max<std::uint64_t>(q.bandwidth, b - a);
            leftmost[b] = std::min(leftmost[b], static_cast<std::uint32_t>(a));
        }
    for (std::size_t v = 0; v < nv; ++v) q.profile += v - leftmost[v];
    const int k = m.corners();
    std::vector<std::uint32_t> spread(ne);
    double sum = 0;
    for (std::size_t e = 0; e < ne; ++e) {
        const auto* c = m.conn.data() + e * k;
        const auto [lo, hi] = std::minmax_element(c, c + k);
        spread[e] = *hi - *lo;
        sum += spread[e];
    }
    q.spread_mean = ne ? sum / static_cast<double>(ne) : 0;
    if (ne) {
        const std::size_t at = std::min(ne - 1, static_cast<std::size_t>(0.95 * static_cast<double>(ne)));
        std::nth_element(spread.begin(), spread.begin() + static_cast<std::ptrdiff_t>(at), spread.end());
        q.spread_p95 = spread[at];
    }
    return q;
}

std::vector<double> shared_key_fraction(const mesh::MeshView& m, Curve c) {
    const int depth = max_depth(m.dim);
    std::vector<std::uint64_t> keys(m.elements);
    compute_keys(m, key_frame(m, depth), c, keys.data());
    std::sort(keys.begin(), keys.end());
    // The key at depth d is the deepest key without its last dim * (depth - d) bits (both curves
    // are refinements of themselves, which the tests check), so one sorted list serves every depth.
    std::vector<double> out;
    for (int d = 1; d <= depth; ++d) {
        const int shift = m.dim * (depth - d);
        std::uint64_t shared = 0;
        for (std::size_t i = 0, j; i < keys.size(); i = j) {
            j = i + 1;
            while (j < keys.size() && (keys[j] >> shift) == (keys[i] >> shift)) ++j;
            if (j - i > 1) shared += j - i;
        }
        out.push_back(keys.empty() ? 0 : static_cast<double>(shared) / static_cast<double>(keys.size()));
    }
    return out;
}

std::pair<std::uint64_t, std::uint64_t> thread_block(std::uint64_t n, int t, int threads) {
    const Block b = static_block(static_cast<std::int64_t>(n), t, threads);
    return {static_cast<std::uint64_t>(b.lo), static_cast<std::uint64_t>(b.hi)};
}

ThreadSharing thread_sharing(const mesh::MeshView& m, int threads) {
    constexpr int none = -1, several = -2;
    std::vector<int> owner(m.vertices, none);
    const int k = m.dim + 1;
    for (int t = 0; t < threads; ++t) {
        const auto [lo, hi] = thread_block(m.elements, t, threads);
        for (std::uint64_t p = lo * k; p < hi * k; ++p) {
            int& o = owner[m.conn[p]];
            o = o == none || o == t ? t : several;
        }
    }
    ThreadSharing s;
    for (int o : owner) s.vertices += o == several;
    for (std::size_t e = 0; e < m.elements; ++e)
        for (int j = 0; j < k; ++j)
            if (owner[m.conn[e * k + j]] == several) {
                ++s.elements;
                break;
            }
    return s;
}

Traversal traversal(std::uint64_t n, int threads) {
    Traversal t;
    t.visit.resize(n);
    t.thread.resize(n);
    t.step.resize(n);
    for (int u = 0; u < threads; ++u) {
        const auto [lo, hi] = thread_block(n, u, threads);
        for (std::uint64_t e = lo; e < hi; ++e) {
            t.visit[e] = static_cast<std::int64_t>(e);
            t.thread[e] = u;
            t.step[e] = static_cast<std::int64_t>(e - lo);
        }
    }
    return t;
}

}  // namespace suite::sfc
