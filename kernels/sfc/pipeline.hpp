#pragma once
// The three phases of reordering a mesh, on arrays the caller owns (a kernel's arena arrays,
// or vectors), so that the measured kernel and the tools run the same code:
//   keys      curves: the bounding box, then key[e] for every element;
//             rcm: the Reverse Cuthill-McKee vertex numbering, then key[e] = the smallest new
//             number among e's corners (elements follow their vertices);
//   sort      perm = elements stably sorted by key;
//   renumber  curves: vertices numbered by first touch along perm; rcm: by the RCM numbering;
//             the connectivity and coordinates rewritten into `out`.
#include <cstdint>
#include <string>
#include <vector>

#include "kernels/mesh/mesh.hpp"
#include "kernels/sfc/keys.hpp"
#include "kernels/sfc/orderings.hpp"
#include "kernels/sfc/radix_sort.hpp"
#include "kernels/sfc/renumber.hpp"

namespace suite::sfc {

struct PipelineArrays {
    std::uint64_t* keys = nullptr;    // elements
    std::uint32_t* perm = nullptr;    // elements
    SortBuffers sort;                 // elements each
    std::uint32_t* new_id = nullptr;  // vertices
    RenumberScratch renumber;         // first-touch scratch (renumber.hpp)
    MeshOut out;                      // connectivity and coordinates of the result
};

class Pipeline {
public:
    // depth: bits a key holds per axis, 1..max_depth(in.dim) (curves only).
    Pipeline(const mesh::MeshView& in, Method method, int depth, Encoder encoder, const PipelineArrays& arrays);
    void keys();
    void sort();
    void renumber();
    int key_bits() const { return method_ == Method::rcm ? 32 : depth_ * in_.dim; }
    const KeyFrame& frame() const { return frame_; }  // set by keys() (curves)

private:
    mesh::MeshView in_;
    Method method_;
    int depth_;
    Encoder encoder_;
    PipelineArrays a_;
    KeyFrame frame_;
};

// Convenience for tools and tests: the mesh reordered by `method` (the kernel's phases, on
// vectors), with perm[i] = the input element that became element i.
struct Reordered {
    mesh::Mesh mesh;
    std::vector<std::uint32_t> perm;
    std::vector<std::uint32_t> new_id;
};
Reordered reorder(const mesh::Mesh& m, Method method, int depth, Encoder encoder = Encoder::best);

// The mesh with its elements in order `perm` and vertex v renumbered new_id[v].
mesh::Mesh permuted(const mesh::Mesh& m, const std::vector<std::uint32_t>& perm,
                    const std::vector<std::uint32_t>& new_id);

// "random": a seeded uniform shuffle of the elements and, independently, of the vertices.
Reordered shuffled(const mesh::Mesh& m, std::uint64_t seed);

// The mesh in one of mesh_orderings() by name (orderings.hpp): as given, shuffled by `seed`, or
// sorted (curves at `depth` bits per axis). Throws UsageError for another name.
mesh::Mesh ordered(const mesh::Mesh& m, const std::string& ordering, std::uint64_t seed, int depth);

}  // namespace suite::sfc
