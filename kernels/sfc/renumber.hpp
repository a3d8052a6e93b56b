#pragma once
// Rewriting a mesh into a new element order: element i of the result is element perm[i] of
// the input; vertices are numbered in the order a loop over the new elements first touches
// them (renumber_first_touch), or by a given map (apply_vertex_order, for RCM). Connectivity
// and coordinates are written to caller-owned arrays; all passes are parallel (OpenMP) and the
// result does not depend on the number of threads.
#include <cstdint>

#include "kernels/mesh/mesh_view.hpp"

namespace suite::sfc {

// Where the rewritten mesh goes (arrays of the input's sizes; z only in 3D).
struct MeshOut {
    std::uint32_t* conn = nullptr;
    double* x = nullptr;
    double* y = nullptr;
    double* z = nullptr;
};

// Scratch of the first-touch numbering, allocated by the caller: `first` has one entry per
// vertex, `bits` and `rank` one per 64 corner positions (rank_words).
struct RenumberScratch {
    std::uint32_t* first = nullptr;
    std::uint64_t* bits = nullptr;
    std::uint32_t* rank = nullptr;
};
inline std::size_t rank_words(std::size_t elements, int corners) {
    return (elements * static_cast<std::size_t>(corners) + 63) / 64;
}

// new_id[v]: vertex v's number in the result. Vertices no element touches (none, in a valid
// mesh) are numbered last, in their old order.
void renumber_first_touch(const mesh::MeshView& in, const std::uint32_t* perm, std::uint32_t* new_id,
                          const RenumberScratch& scratch, const MeshOut& out);

// The same rewrite with the vertex numbers given (new_id, a permutation).
void apply_vertex_order(const mesh::MeshView& in, const std::uint32_t* perm, const std::uint32_t* new_id,
                        const MeshOut& out);

}  // namespace suite::sfc
