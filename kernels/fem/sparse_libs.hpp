#pragma once
// What `suite matrix` takes from the libraries that define it rather than writing its own:
// approximate minimum degree (SuiteSparse AMD), nested dissection (METIS_NodeND) and a sparse
// Cholesky factorisation (SuiteSparse CHOLMOD). Built only when CMake found them
// (SUITE_HAVE_SPARSE); otherwise sparse_libs_missing() names the packages and the rest of the
// suite builds as before.
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "kernels/fem/matrix_study.hpp"

namespace suite::fem {

// "" when built with the libraries, else which are missing and the Debian package of each.
std::string sparse_libs_missing();
// The libraries' versions, for the records: {"amd": "2.4.6", "cholmod": "3.0.14", "metis": "5.1.0"}.
std::vector<std::pair<std::string, std::string>> sparse_lib_versions();

// Fill-reducing orderings of a's pattern, perm[new] = old.
std::vector<std::uint32_t> amd_order(const Csr& a);
std::vector<std::uint32_t> nested_dissection_order(const Csr& a);  // on the graph without the diagonal

// CHOLMOD's symbolic analysis of a (as numbered: no ordering of CHOLMOD's own, no postorder).
struct Symbolic {
    double factor_nnz = 0;  // nonzeros of L, diagonal included
    double flops = 0;       // of the numeric factorisation
    double seconds = 0;
};
Symbolic analyse(const Csr& a);

// The numeric factorisation A = L Lᵀ, `reps` times, and as many solves of A x = b with b = A·1.
struct Factorisation {
    std::string method;  // "supernodal LLᵀ" (always asked for: the LDLᵀ would not notice an indefinite A)
    double factor_nnz = 0, flops = 0;
    double analyse_seconds = 0;
    std::vector<double> factor_seconds, solve_seconds;
    double residual = 0;   // ||b - A x|| / ||b|| of the last solve
    double max_error = 0;  // max |x_i - 1|
};
// Throws NotDefinite when a is not positive definite (CHOLMOD stops at a leading minor).
struct NotDefinite : std::runtime_error {
    std::int64_t minor;
    NotDefinite(std::int64_t m, const std::string& what) : std::runtime_error(what), minor(m) {}
};
Factorisation factorise(const Csr& a, int reps);

// Solves a x = b by CHOLMOD's supernodal LLᵀ in its own default ordering (the implicit MPM's
// reference solve), with the seconds of each phase in `times` when given. Throws NotDefinite.
struct CholeskyTimes {
    double analyse = 0, factorise = 0, solve = 0;
};
std::vector<double> cholesky_solve(const Csr& a, const std::vector<double>& b, CholeskyTimes* times = nullptr);

// CHOLMOD with its own default ordering: whether a is positive definite, for the check made
// before anything is written. Throws NotDefinite.
void check_definite(const Csr& a);

}  // namespace suite::fem
