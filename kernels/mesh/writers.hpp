#pragma once
// Mesh writers, returning the file's content (callers write it with write_atomically, so no
// half-written file is ever left): Gmsh .msh ASCII (2.2 or 4.1, read back exactly by
// read_msh: coordinates are written in the shortest form that reads back to the same double)
// and VTK .vtu (ASCII UnstructuredGrid, for ParaView) with optional per-element fields.
#include <cstdint>
#include <string>
#include <vector>

#include "kernels/mesh/mesh.hpp"

namespace suite::mesh {

std::string msh_text(const Mesh& m, const std::string& version);  // "2.2" or "4.1"

struct CellField {
    std::string name;
    std::vector<std::int64_t> values;  // one per element
};
std::string vtu_text(const Mesh& m, const std::vector<CellField>& fields = {});

}  // namespace suite::mesh
