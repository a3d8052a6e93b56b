#pragma once
// The unique edges of a mesh, stored by their lower vertex: the edges of vertex v are
// (v, upper[k]) for k in [row[v], row[v+1]), upper ascending within a row. An edge's id is its
// position k. Refinement numbers edge midpoints by it; the vertex graph (RCM, bandwidth,
// profile) is the symmetric closure of these edges.
#include <cstdint>
#include <vector>

#include "kernels/mesh/mesh_view.hpp"

namespace suite::mesh {

struct EdgeTable {
    std::vector<std::uint64_t> row;    // vertices + 1 entries
    std::vector<std::uint32_t> upper;  // one per edge

    std::size_t count() const { return upper.size(); }
    // The id of edge {a, b}; the edge must exist.
    std::uint64_t find(std::uint32_t a, std::uint32_t b) const {
        const std::uint32_t lo = a < b ? a : b, hi = a < b ? b : a;
        std::uint64_t k = row[lo];
        while (upper[k] != hi) ++k;  // rows hold a handful of edges: a scan beats a search
        return k;
    }
};

// The local corner pairs of an element's edges: 3 for a triangle, 6 for a tetrahedron.
inline int edge_count(int dim) { return dim == 2 ? 3 : 6; }
inline const int (*local_edges(int dim))[2] {
    static const int tri[3][2] = {{0, 1}, {1, 2}, {2, 0}};
    static const int tet[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};
    return dim == 2 ? tri : tet;
}

// Built in parallel (OpenMP); the result does not depend on the number of threads.
EdgeTable build_edges(const MeshView& m);

}  // namespace suite::mesh
