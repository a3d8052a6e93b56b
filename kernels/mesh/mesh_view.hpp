#pragma once
// A read-only view on a mesh's arrays wherever they live (a Mesh, or the arena arrays of a
// kernel). A plain aggregate with no functions, so that code compiled for another instruction
// set (kernels/sfc/keys_pdep.cpp) can include it without sharing inline code.
#include <cstddef>
#include <cstdint>

namespace suite::mesh {

struct MeshView {
    int dim = 2;  // 2: triangles, 3: tetrahedra
    std::size_t vertices = 0;
    std::size_t elements = 0;
    const double* x = nullptr;
    const double* y = nullptr;
    const double* z = nullptr;            // null in 2D
    const std::uint32_t* conn = nullptr;  // dim + 1 corners per element, element after element
};

}  // namespace suite::mesh
