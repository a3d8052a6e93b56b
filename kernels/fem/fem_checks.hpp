#pragma once
// The checks behind the finite element kernels' verify(), each computed another way than the
// kernel computes: the pattern against the mesh's edge table, the matrices against a serial
// reference assembly, and properties that hold whatever the assembly order (symmetry, the mass
// matrix's total equal to the mesh's area, A 1 = -(k² mass term) 1 because the stiffness part
// of A annihilates constants). Each returns "" when the check holds, else what failed.
#include <string>

#include "kernels/fem/assembly.hpp"
#include "kernels/fem/csr.hpp"

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
std::string check_same_lambda(const std::string& key, const std::string& who, double lambda);

}  // namespace suite::fem
