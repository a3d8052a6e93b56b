#pragma once
// How good an ordering is for memory, as numbers.
#include <cstdint>
#include <vector>

#include "kernels/mesh/mesh.hpp"
#include "kernels/sfc/keys.hpp"

namespace suite::sfc {

struct OrderingQuality {
    // The vertex graph as a matrix in the mesh's numbering: bandwidth = max |i - j| over edges;
    // profile = sum over rows i of (i - the smallest j <= i adjacent to i, or i itself).
    std::uint64_t bandwidth = 0;
    std::uint64_t profile = 0;
    // Per element, the distance in memory between the vertices it touches: the largest minus
    // the smallest vertex number (times 8 bytes in each coordinate array); mean and 95th percentile.
    double spread_mean = 0;
    std::uint64_t spread_p95 = 0;
};
OrderingQuality ordering_quality(const mesh::Mesh& m);

// The thesis's "relative error" of a curve: for depth d = 1..max_depth, the fraction of elements
// whose key at depth d equals another element's (elements no key tells apart). result[d - 1].
std::vector<double> shared_key_fraction(const mesh::MeshView& m, Curve c);

// A loop over the elements split among `threads` in static blocks (as the harness splits it):
// elements with a vertex that an element of another thread also has (the points where a
// parallel assembly must synchronise), and those vertices.
struct ThreadSharing {
    std::uint64_t elements = 0;
    std::uint64_t vertices = 0;
};
ThreadSharing thread_sharing(const mesh::MeshView& m, int threads);

// Thread t's block [lo, hi) of n elements: the harness's static split (static_block).
std::pair<std::uint64_t, std::uint64_t> thread_block(std::uint64_t n, int t, int threads);

// How such a loop walks n elements, per element (what `suite traverse` draws): its visit index,
// the thread that owns it, and its step within that thread's block.
struct Traversal {
    std::vector<std::int64_t> visit, thread, step;
};
Traversal traversal(std::uint64_t n, int threads);

}  // namespace suite::sfc
