#pragma once
// Reverse Cuthill-McKee numbering of a mesh's vertex graph (two vertices adjacent when an
// element has both), by Boost.Graph: the classical bandwidth-reducing alternative to curves.
#include <cstdint>

#include "kernels/mesh/mesh_view.hpp"

namespace suite::sfc {

// new_id[v] for every vertex: a permutation. One starting vertex per connected component
// (Boost's pseudo-peripheral choice). The graph is built and freed inside the call.
void rcm_vertex_order(const mesh::MeshView& m, std::uint32_t* new_id);

}  // namespace suite::sfc
