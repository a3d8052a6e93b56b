#pragma once
// Compressed sparse row storage of the P1 matrices, on arrays the caller owns (a kernel's arena
// arrays in the measured kernels, vectors in tests and tools), and the operations every finite
// element kernel shares: the sparsity pattern of a triangle mesh, a row lookup, y = A x.
// Indices are 32-bit (fem_mesh.hpp refuses a mesh whose matrix would have 2^32 nonzeros or more):
// the index arrays are half of SpMV's traffic, and 64-bit ones would cost a third more of it.
#include <cstdint>

namespace suite::fem {

// A triangle mesh as the kernels hold it: coordinates per vertex, three corners per element.
struct MeshArrays {
    std::int64_t nv = 0, ne = 0;
    const double* x = nullptr;
    const double* y = nullptr;
    const std::uint32_t* conn = nullptr;
};

// The pattern: row v holds v and every vertex that shares a triangle with it, columns ascending.
struct Pattern {
    std::int64_t n = 0;
    std::uint32_t* row_ptr = nullptr;  // n + 1
    std::uint32_t* col = nullptr;      // row_ptr[n]
    std::uint64_t nnz() const { return row_ptr[n]; }
};

// Scratch of build_pattern: the vertex-to-triangle lists and the team's scan sums.
struct PatternScratch {
    std::uint32_t* v2e_ptr = nullptr;  // nv + 1
    std::uint32_t* v2e = nullptr;      // 3 ne
    std::uint32_t* fill = nullptr;     // nv
    std::uint64_t* partial = nullptr;  // threads + 1
};

// Builds row_ptr (and, when p.col is not null, the columns) of the mesh's pattern, with the
// current OpenMP team: triangles split in blocks for the vertex-to-triangle lists, vertices in
// blocks for the rows (the split of first touch). With p.col null, only row_ptr is made, so that
// the caller can allocate the columns once it knows how many there are.
void build_pattern(const MeshArrays& mesh, Pattern& p, const PatternScratch& scratch);

// The position of column j in row i, or -1 (rows hold about 7 entries: a linear scan).
inline std::int64_t find_entry(const Pattern& p, std::uint32_t i, std::uint32_t j) {
    for (std::uint32_t k = p.row_ptr[i], end = p.row_ptr[i + 1]; k < end; ++k)
        if (p.col[k] == j) return k;
    return -1;
}

// y[i] = Σ_k val[k] x[col[k]] for rows [lo, hi): one thread's share of y = A x.
inline void spmv_rows(const Pattern& p, const double* val, const double* x, double* y, std::int64_t lo,
                      std::int64_t hi) {
    const std::uint32_t* const rp = p.row_ptr;
    const std::uint32_t* const col = p.col;
    for (std::int64_t i = lo; i < hi; ++i) {
        double s = 0;
        for (std::uint32_t k = rp[i], end = rp[i + 1]; k < end; ++k) s += val[k] * x[col[k]];
        y[i] = s;
    }
}

}  // namespace suite::fem
