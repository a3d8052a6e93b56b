#pragma once
// Mesh generators and uniform refinement. Orders are deterministic (independent of the number
// of threads): they are the meshes' "natural" order.
#include <cstdint>

#include "kernels/mesh/mesh.hpp"

namespace suite::mesh {

// Each triangle into 4 through its edge midpoints, each tetrahedron into 8 (Bey's rule: four
// corner children, the inner octahedron cut along the diagonal between the midpoints of edges
// 0-2 and 1-3). Children keep their parent's orientation. The old vertices keep their numbers
// and the midpoints follow them, one per edge (numbered by lower vertex, then upper vertex);
// the children of element e are elements 4e..4e+3 (8e..8e+7).
Mesh refine_uniform(const Mesh& m);

// The unit disk: a hexagon of 6 triangles around the origin, refined `refine` times, then every
// vertex pushed out radially so that the hexagon's boundary lands on the unit circle.
// 6 * 4^refine triangles.
Mesh disk_mesh(int refine);

// The box [0,1]^3 in nx * ny * nz cubes, each cut into 6 tetrahedra around its diagonal from
// (0,0,0) to (1,1,1) (Kuhn's cut, conforming between cubes). Cubes in x-fastest order.
Mesh box_mesh(std::uint32_t nx, std::uint32_t ny, std::uint32_t nz);

}  // namespace suite::mesh
