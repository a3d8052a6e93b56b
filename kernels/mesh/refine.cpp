// Uniform refinement; see generate.hpp.
#include <stdexcept>

#include "kernels/mesh/edges.hpp"
#include "kernels/mesh/generate.hpp"

namespace suite::mesh {

namespace {

// Children as corner lists over the parent's corners 0..k-1 and edge midpoints 4+j (j in
// local_edges order). Each child's orientation equals its parent's: the ratio of the two
// determinants is a constant of the affine map (1/4, 1/8), checked by the tests.
constexpr int tri_children[4][3] = {{0, 4, 6}, {4, 1, 5}, {6, 5, 2}, {4, 5, 6}};  // midpoints 01, 12, 20
// Midpoints: 4:01 5:02 6:03 7:12 8:13 9:23.
constexpr int tet_children[8][4] = {{0, 4, 5, 6}, {4, 1, 7, 8}, {5, 7, 2, 9}, {6, 8, 9, 3},
                                    {4, 5, 6, 8}, {4, 5, 8, 7}, {5, 6, 8, 9}, {5, 7, 9, 8}};

}  // namespace

Mesh refine_uniform(const Mesh& m) {
    const MeshView v = m.view();
    const EdgeTable edges = build_edges(v);
    const std::size_t nv = m.vertices(), nedges = edges.count();
    if (nv + nedges >= UINT32_MAX) throw std::length_error("refinement would need more than 2^32 - 1 vertices");
    Mesh r;
    r.dim = m.dim;
    r.x.resize(nv + nedges);
    r.y.resize(nv + nedges);
    if (m.dim == 3) r.z.resize(nv + nedges);
    const std::int64_t nvi = static_cast<std::int64_t>(nv);
#pragma omp parallel for schedule(static)
    for (std::int64_t a = 0; a < nvi; ++a) {
        r.x[a] = m.x[a];
        r.y[a] = m.y[a];
        if (m.dim == 3) r.z[a] = m.z[a];
        for (std::uint64_t k = edges.row[a]; k < edges.row[a + 1]; ++k) {
            const std::uint32_t b = edges.upper[k];
            r.x[nv + k] = 0.5 * (m.x[a] + m.x[b]);
            r.y[nv + k] = 0.5 * (m.y[a] + m.y[b]);
            if (m.dim == 3) r.z[nv + k] = 0.5 * (m.z[a] + m.z[b]);
        }
    }
    const int k = m.corners(), ec = edge_count(m.dim), nchild = m.dim == 2 ? 4 : 8;
    const auto* pairs = local_edges(m.dim);
    const std::int64_t ne = static_cast<std::int64_t>(m.elements());
    r.conn.resize(m.conn.size() * static_cast<std::size_t>(nchild));
#pragma omp parallel for schedule(static)
    for (std::int64_t e = 0; e < ne; ++e) {
        const std::uint32_t* c = m.conn.data() + e * k;
        std::uint32_t p[10];  // corners at 0..k-1, midpoints at 4..
        for (int i = 0; i < k; ++i) p[i] = c[i];
        for (int j = 0; j < ec; ++j)
            p[4 + j] = static_cast<std::uint32_t>(nv + edges.find(c[pairs[j][0]], c[pairs[j][1]]));
        std::uint32_t* out = r.conn.data() + e * k * nchild;
        for (int ch = 0; ch < nchild; ++ch)
            for (int i = 0; i < k; ++i) out[ch * k + i] = p[m.dim == 2 ? tri_children[ch][i] : tet_children[ch][i]];
    }
    return r;
}

}  // namespace suite::mesh
