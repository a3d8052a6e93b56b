#include "kernels/fem/fem_mesh.hpp"

#include <map>
#include <mutex>
#include <vector>

#include "harness/common/units.hpp"
#include "kernels/mesh/edges.hpp"
#include "kernels/sfc/encode.hpp"
#include "kernels/sfc/pipeline.hpp"

namespace suite::fem {

std::uint64_t pattern_nonzeros(const mesh::Mesh& m) { return m.vertices() + 2 * mesh::build_edges(m.view()).count(); }

void check_fem_mesh(const mesh::Mesh& m, const std::string& spec) {
    const std::string where = "--mesh=" + spec + ": ";
    if (m.dim != 2)
        throw UsageError(where + "the finite element kernels need a triangle mesh, and this one is made of " +
                         mesh::element_word(m.dim, true) + "; accepted: disk:refine=K or file:PATH of triangles");
    const std::size_t ne = m.elements(), nv = m.vertices();
    std::vector<std::uint8_t> used(nv, 0);
    for (std::uint32_t v : m.conn) used[v] = 1;
    for (std::size_t v = 0; v < nv; ++v)
        if (!used[v])
            throw UsageError(where + "vertex " + std::to_string(v) +
                             " belongs to no triangle (an isolated vertex leaves the mass matrix singular); " +
                             "remove it from the mesh");
    // The orientation of the first triangle is the mesh's; a triangle turning the other way is
    // folded over its neighbours (readers already refuse degenerate ones).
    const mesh::MeshView view = m.view();
    const bool positive = mesh::signed_measure(view, 0) > 0;
    for (std::size_t e = 0; e < ne; ++e)
        if ((mesh::signed_measure(view, e) > 0) != positive)
            throw UsageError(where + "triangle " + std::to_string(e) + " is inverted (" +
                             (positive ? "clockwise" : "counter-clockwise") +
                             ", triangle 0 the other way round); every triangle must have the same orientation");
    if (const std::uint64_t nz = pattern_nonzeros(m); nz > 0xffffffffULL)
        throw UsageError(where + "its matrices would have " + std::to_string(nz) +
                         " nonzeros, more than the 4294967295 that 32-bit indices address; use a smaller mesh");
}

void check_fem_spec(const std::string& spec) {
    static std::mutex lock;
    static std::map<std::string, std::string> checked;  // spec -> "" or the error
    const std::lock_guard<std::mutex> hold(lock);
    auto it = checked.find(spec);
    if (it == checked.end()) {
        std::string error;
        try {
            check_fem_mesh(mesh::load_mesh(mesh::parse_mesh_spec(spec)), spec);
        } catch (const UsageError& e) {
            error = e.what();
        }
        it = checked.emplace(spec, error).first;
    }
    if (!it->second.empty()) throw UsageError(it->second);
}

mesh::Mesh load_fem_mesh(const std::string& spec, const std::string& ordering, std::uint64_t seed) {
    fem_orderings().at(ordering);
    mesh::Mesh m = mesh::load_mesh(mesh::parse_mesh_spec(spec));
    check_fem_mesh(m, spec);
    return sfc::ordered(m, ordering, seed, sfc::max_depth(2));
}

}  // namespace suite::fem
