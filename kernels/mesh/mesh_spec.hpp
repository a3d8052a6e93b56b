#pragma once
// The --mesh option: which mesh a command works on.
//   disk:refine=K                 the generated unit disk (6 * 4^K triangles)
//   box:NX,NY,NZ[:refine=K]       the generated unit cube (6 * NX*NY*NZ * 8^K tetrahedra)
//   file:PATH[:refine=K]          a Gmsh .msh (2.2, 4.1 ASCII) or thesis .txt file, refined K times
// Parsing and counting check everything (a bad file is reported by name and line) before any
// large allocation; load_mesh then builds the mesh.
#include <cstdint>
#include <string>
#include <string_view>

#include "kernels/mesh/mesh.hpp"

namespace suite::mesh {

struct MeshSpec {
    enum class Kind { disk, box, file } kind = Kind::disk;
    int refine = 0;
    std::uint32_t nx = 0, ny = 0, nz = 0;
    std::string path;
    std::string text;  // as given
};

// Throws UsageError naming the text and what is accepted.
MeshSpec parse_mesh_spec(std::string_view text);

// Exact sizes of the mesh a spec describes, from the counts of the unrefined mesh and the
// refinement recurrences (a file is read, once per process, to count it).
struct MeshCounts {
    int dim = 2;
    std::uint64_t vertices = 0, elements = 0;
};
MeshCounts mesh_counts(const MeshSpec& spec);

// The most elements a mesh may have: element and corner positions (4 a tetrahedron) are 32-bit.
constexpr std::uint64_t max_elements = (1ULL << 30) - 1;

Mesh load_mesh(const MeshSpec& spec);

// The generated disk with the fewest refinements that has at least `elements` triangles, for
// kernels sized by a count rather than a mesh.
std::string disk_spec_for(std::uint64_t elements);

}  // namespace suite::mesh
