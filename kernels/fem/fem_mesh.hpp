#pragma once
// The mesh of a finite element point: loaded from its --mesh spec, checked for what the P1
// problem needs beyond what every reader checks, and put in the point's ordering before any
// matrix is built. Problems are UsageErrors (exit status 2) that name the mesh.
#include <cstdint>
#include <string>

#include "kernels/mesh/mesh.hpp"
#include "kernels/mesh/mesh_spec.hpp"
#include "kernels/sfc/orderings.hpp"

namespace suite::fem {

// The orderings the finite element kernels accept: each mesh order once (kernels/sfc/orderings.hpp).
inline const ChoiceTable<sfc::Ordering>& fem_orderings() { return sfc::distinct_orderings(); }

// Refuses, naming the first offender: a mesh that is not made of triangles; a vertex that belongs
// to no triangle (its row of M would be zero: the mass matrix singular); a triangle whose
// orientation is opposite to the others' (a folded, inverted mesh). Also a mesh whose matrix would
// need 2^32 nonzeros or more (32-bit indices, csr.hpp).
void check_fem_mesh(const mesh::Mesh& m, const std::string& spec);

// Loads the spec's mesh and checks it (once per spec and process: validate() calls it for every
// point), without reordering: for validate().
void check_fem_spec(const std::string& spec);

// The mesh of the spec, checked, in `ordering`, one of fem_orderings() (a random one shuffled by
// `seed`); another name is a UsageError naming them.
mesh::Mesh load_fem_mesh(const std::string& spec, const std::string& ordering, std::uint64_t seed);

// Nonzeros of the P1 pattern: one per vertex and two per edge.
std::uint64_t pattern_nonzeros(const mesh::Mesh& m);

}  // namespace suite::fem
