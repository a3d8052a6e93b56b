#pragma once
// `suite matrix`'s study, callable without it: the P1 Helmholtz matrix A of a mesh assembled once
// in the mesh's own order, then, per vertex ordering, P A Pᵀ with its bandwidth and profile, the
// time to compute the ordering, CHOLMOD's Cholesky factor (analysed always; computed, timed and
// checked when it fits the caller's limit) and the suite's SpMV on the permuted matrix, checked
// against the unpermuted product. Every check that fails throws std::runtime_error: a number
// from a wrong computation is not returned. The program renders the results.
#include <cstdint>
#include <string>
#include <vector>

#include "harness/common/choice_table.hpp"
#include "kernels/fem/matrix_study.hpp"
#include "kernels/fem/sparse_libs.hpp"
#include "kernels/mesh/mesh.hpp"
#include "kernels/mesh/mesh_spec.hpp"

namespace suite::fem {

// `suite matrix`'s orderings: the finite element kernels' mesh orderings (fem_orderings(): they
// number the mesh's vertices, and A's rows follow), then two orderings of A's graph itself by a
// library. Those two extend the mesh table here instead of sitting in it: they exist only where
// an assembled A does, so every other user of the mesh table (the kernels, sfc-build, traverse)
// would have to skip them. They need no check of their own: `suite matrix` refuses to start
// without SuiteSparse and METIS (sparse_libs_missing()).
struct MatrixOrdering {
    enum class From { mesh, amd, nested_dissection };
    From from = From::mesh;
    std::string source;  // who computes it, as the records say
};
const ChoiceTable<MatrixOrdering>& matrix_orderings();

// A, and the product every ordering's SpMV must reproduce.
struct MatrixUnderStudy {
    Csr a;
    double asymmetry = 0;          // what symmetrize_from_lower removed
    std::vector<double> x, y_ref;  // y_ref = A x
};

// The memory the study takes at its peak, from the mesh's counts alone (before anything is
// built): the mesh while loaded, checked and ordered, A as assembled and permuted, CHOLMOD's
// copy for its analysis, the vectors; not the factor, which each ordering computes only when it
// fits both its limit and the memory then available.
std::uint64_t study_bytes(const mesh::MeshCounts& c);

// Assembles A of `m` at δ, makes it exactly symmetric and checks that it is positive definite
// (NotDefinite otherwise: it has no Cholesky factor).
MatrixUnderStudy prepare_matrix(const mesh::Mesh& m, double delta);

struct StudySettings {
    int reps = 5;                 // factorisations, solves and SpMVs timed
    int threads = 1;              // of the SpMV
    double max_factor_bytes = 0;  // a factor larger than this is analysed, not computed
    std::uint64_t seed = 1;       // of the random ordering
    int spy_bins = 256;
};

struct OrderingStudy {
    std::string name;    // natural, random, morton, hilbert, rcm, amd, nd
    std::string source;  // who computed it: the mesh toolkit, SuiteSparse AMD, METIS_NodeND
    double order_s = 0;  // computing the ordering
    Structure structure;
    Symbolic symbolic;
    double factor_bytes = 0;          // a value and a row index per nonzero of L
    bool factorised = false;          // false: over max_factor_bytes, or over the memory available
    bool factor_over_memory = false;  // not factorised for want of memory (within max_factor_bytes)
    double memory_available = 0;      // bytes, when it was checked
    Factorisation factor;             // when factorised
    double factor_median_s = 0, solve_median_s = 0;
    std::vector<double> spmv_seconds;
    double spmv_median_s = 0;
    double spmv_max_error = 0;  // of each row, relative to its Σ|a x|
    double spmv_bytes = 0;      // values, column indices, row pointers, x and y once each
    int spy_bins = 0;
    std::vector<std::uint64_t> spy;
    Csr permuted;  // P A Pᵀ, for an export
};

// One ordering of the matrix of `m` (the one prepare_matrix was given).
OrderingStudy study_ordering(const MatrixUnderStudy& mat, const mesh::Mesh& m, const std::string& name,
                             const StudySettings& settings);

// y = B x with the fem-spmv loop, `threads` threads in static row blocks.
void spmv(const Csr& b, const double* x, double* y, int threads);

}  // namespace suite::fem
