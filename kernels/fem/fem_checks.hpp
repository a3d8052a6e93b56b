#pragma once
// The checks behind the finite element kernels' verify(), each computed another way than the
// kernel computes: the pattern against the mesh's edge table, the matrices against a serial
// reference assembly, and properties that hold whatever the assembly order (symmetry, the mass
// matrix's total equal to the mesh's area, A 1 = -(k² mass term) 1 because the stiffness part
// of A annihilates constants). Each returns "" when the check holds, else what failed.
#include <functional>
#include <string>

#include "kernels/fem/assembly.hpp"
#include "kernels/fem/csr.hpp"
#include "kernels/fem/solver.hpp"

namespace suite::fem {

// Rows ascending with no repeat, the diagonal present, both triangles' corners of every
// element pair present, symmetric, and exactly nv + 2 x edges entries.
std::string check_pattern(const MeshArrays& mesh, const Pattern& p);

// Entry by entry against the serial reference, to `rel` of the row's largest entry.
std::string check_against(const Matrices& got, AssembledCsr& ref, double rel);

// A and M symmetric to `rel` of the row's largest entry; Σ M = the area (from the coordinates);
// Σ_j A_ij = -∫ k² φ_i, that integral by its own loop over the triangles.
std::string check_properties(const MeshArrays& mesh, const Matrices& got, double delta, double rel);

// λ of one problem (`key`: the mesh and parameters, and whatever else must match) must come out
// the same whatever the ordering or partition: the first point of this process with that key is
// remembered, and every later one (`who` names it) must agree with it to 1e-7 relative.
// How far ||f - A x|| / ||f|| of a converged CG solution may lie above the tolerance the run asked
// for, from rounding alone. CG stops on its recursive residual, which drifts from the true one: each
// iteration's updates round at about u ||A|| ||x|| (u = 2^-53), and the norms of CG's iterates from
// x = 0 grow monotonically (Hestenes and Stiefel), so the final x bounds them all; the recomputing
// product itself rounds by at most γ_w |A| |x| for rows of w entries. Hence 2 u (iterations + w + 2)
// || |A| |x| || / ||f||: about 1e-13 on the suite's meshes, a thousandth of the default tolerance,
// where a solver that stops early misses it by its own margin.
double cg_rounding_margin(long iterations, std::int64_t longest_row, double abs_ax_norm, double f_norm);

// The verdict on a CG solution whose true residual ||f - A x|| / ||f|| is `rel` and whose recursive
// one, where CG stopped, is `recursive`: "" when both hold (see check_cg_solution), else what failed.
std::string judge_cg_residuals(double rel, double recursive, double tol, double margin);

// The solution x of a CG solve of A x = f that claimed `result` at tolerance `tol`: its recursive
// residual within tol, and its true one, recomputed, within tol plus the rounding margin. "" when it
// holds, else what failed; `detail` gets the recomputed figures either way.
std::string check_cg_solution(const Pattern& p, const double* a, const double* f, const double* x,
                              const CgResult& result, double tol, std::string& detail);

// What verify() says of a CG solve (cg) or an inverse iteration, whoever ran it: that it ran after
// setup, that it converged (else `solver_failed`, and which limit stopped it), and that it took
// the CG iterations the untimed solve of setup took. Each failure goes to `fail`.
struct SolveOutcome {
    bool ran = false, cg = true;
    CgResult cg_result;
    EigenResult eigen;
    long setup_cg_iterations = 0;
    double cg_tol = 0, tol = 0;
    int max_cg = 0;
    long cg_iterations() const { return cg ? cg_result.iterations : eigen.cg_iterations; }
};
void check_solve_outcome(const SolveOutcome& o, bool& solver_failed,
                         const std::function<void(const std::string&)>& fail);

// y, the symmetric product (symmetric.hpp) of x: equal to the last bit to a serial replay of the
// team's schedule (a race would differ) and, entry by entry, to the full CSR product to 1e-12 of
// the row's Σ_j |a_ij x_j| (the storage and the window are right). "" when both hold, else the
// first difference; `detail` gets the largest relative difference either way.
std::string check_symmetric_product(const Pattern& p, const double* a, const SymmetricPattern& s, SymmetricValues v,
                                    const double* x, const double* y, std::string& detail);

std::string check_same_lambda(const std::string& key, const std::string& who, double lambda);

}  // namespace suite::fem
