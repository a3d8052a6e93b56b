#pragma once
// Mesh readers. Each returns a mesh that passed every check (counts, indices in range, finite
// coordinates, no degenerate element, at least one element) or throws MeshError, whose message
// is "NAME:LINE: what is wrong" (a usage error: exit status 2). `name` is what messages call
// the text, normally its file name.
#include <string>
#include <string_view>
#include <vector>

#include "kernels/mesh/mesh.hpp"

namespace suite::mesh {

// The thesis's text format (../shared/meshes/README.md): "<N> vertices in the domain", a
// header line, N lines "id x y" (ids 0, 1, 2, ... in order); "<M> faces in the domain" (or
// "elements"), a header line, M lines "v0 v1 v2" (0-based). Triangles only.
Mesh read_text_mesh(std::string_view text, const std::string& name);

// Gmsh .msh, ASCII, versions 2.2 and 4.1. The mesh is made of the elements of the highest
// dimension present, which must all be 3-node triangles (type 2) or all 4-node tetrahedra
// (type 4); points, lines and, in a 3D mesh, triangles are boundary entities and ignored. A 2D
// mesh must lie in the plane z = 0. Node tags may be any positive integers.
Mesh read_msh(std::string_view text, const std::string& name);

// Reads the file at `path`, choosing the reader by its first line ($MeshFormat: Gmsh).
Mesh read_mesh_file(const std::string& path);

// The checks every reader ends with: at least one element, no degenerate element (reported
// at `element_lines[e]`, the line the element came from).
void check_read_mesh(const Mesh& m, const std::vector<std::uint32_t>& element_lines, const std::string& name,
                     std::size_t last_line);

}  // namespace suite::mesh
