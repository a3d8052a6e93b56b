#pragma once
// A triangle (2D) or tetrahedron (3D) mesh in structure-of-arrays form: one array per
// coordinate axis, and one connectivity array holding each element's dim + 1 corners together
// (an element loop reads all corners of one element at once), vertex indices 0-based. Plain
// data: the generators, readers and orderings build it; nothing here checks it (check_mesh does).
#include <cstdint>
#include <string>
#include <vector>

#include "kernels/mesh/mesh_view.hpp"

namespace suite::mesh {

struct Mesh {
    int dim = 2;
    std::vector<double> x, y, z;  // z is empty in 2D
    std::vector<std::uint32_t> conn;

    int corners() const { return dim + 1; }
    std::size_t vertices() const { return x.size(); }
    std::size_t elements() const { return conn.size() / static_cast<std::size_t>(corners()); }
    MeshView view() const {
        return {dim, vertices(), elements(), x.data(), y.data(), dim == 3 ? z.data() : nullptr, conn.data()};
    }
};

// Twice the signed area of triangle e (2D) or six times the signed volume of tetrahedron e (3D).
double signed_measure(const MeshView& m, std::size_t e);

// Whether element e is degenerate: a repeated corner, or a measure that is zero up to rounding
// (|measure| <= 1e-13 times its longest edge to the power dim).
bool degenerate(const MeshView& m, std::size_t e);

// "triangle" / "tetrahedron", with "s" when plural.
std::string element_word(int dim, bool plural = false);

}  // namespace suite::mesh
