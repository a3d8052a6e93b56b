#pragma once
// The structure of the P1 matrix under a vertex ordering (`suite matrix`): the symmetric
// permutation P A Pᵀ, its bandwidth and profile, a spy grid for the figures, Matrix Market text,
// and the vertex orderings the mesh toolkit gives (the fill-reducing ones come from SuiteSparse
// and METIS, sparse_libs.hpp).
#include <cstdint>
#include <string>
#include <vector>

#include "kernels/mesh/mesh.hpp"

namespace suite::fem {

// A square sparse matrix in CSR, columns ascending in every row.
struct Csr {
    std::int64_t n = 0;
    std::vector<std::uint32_t> row_ptr{0}, col;
    std::vector<double> val;
    std::uint64_t nnz() const { return row_ptr.back(); }
};

// perm[new] = old: the vertex that takes number `new`. True when perm holds 0..n-1 once each.
bool is_permutation(const std::vector<std::uint32_t>& perm, std::size_t n);
std::vector<std::uint32_t> inverse_permutation(const std::vector<std::uint32_t>& perm);

// Sets every upper entry a[j][i] to its lower twin a[i][j] (i > j). Assembly adds an element's
// contributions to (i, j) and (j, i) in different orders, so the two differ by round-off; a
// matrix exactly symmetric keeps the same values whichever triangle a renumbering (or CHOLMOD,
// or a Matrix Market file) keeps. Returns the largest relative change. The pattern must be
// symmetric.
double symmetrize_from_lower(Csr& a);

// B = P A Pᵀ with B[i][j] = A[perm[i]][perm[j]]: the same matrix with the unknowns renumbered.
Csr permute_symmetric(const Csr& a, const std::vector<std::uint32_t>& perm);

struct Structure {
    std::uint64_t bandwidth = 0;  // max |i - j| over the nonzeros
    std::uint64_t profile = 0;    // Σ_i (i - the first column of row i), the lower envelope's size
};
Structure structure(const Csr& a);

// Nonzeros per block of a bins x bins grid laid over the matrix (bins = min(n, max_bins)), row
// major: what a spy plot of a million rows shows at a page's resolution.
std::vector<std::uint64_t> spy_grid(const Csr& a, int max_bins, int* bins);

// Matrix Market coordinate text, `real symmetric` (the lower triangle, 1-based), with the comment
// lines given (each becomes a '%' line).
std::string matrix_market(const Csr& a, const std::vector<std::string>& comments);

// The vertex order, perm[new] = old, of one of the finite element kernels' mesh orderings
// (fem_orderings(), kernels/fem/fem_mesh.hpp; a random one shuffled by `seed`). Throws
// UsageError naming them for another name.
std::vector<std::uint32_t> mesh_vertex_order(const mesh::Mesh& m, const std::string& name, std::uint64_t seed);

}  // namespace suite::fem
