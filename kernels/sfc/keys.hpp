#pragma once
// Keys of mesh elements along a space-filling curve: each element's centroid, placed in the
// mesh's bounding box (computed from the vertices, never assumed), quantized at `depth` bits
// an axis and encoded (encode.hpp). Computed in parallel over static blocks of elements.
#include <cstdint>
#include <string>

#include "kernels/mesh/mesh_view.hpp"
#include "kernels/sfc/encode.hpp"

namespace suite::sfc {

enum class Curve { morton, hilbert, morton_recursive };
// How Morton bits are interleaved: `best` is BMI2 pdep when the build targets a CPU with BMI2
// (-march), the portable spreading otherwise.
enum class Encoder { best, portable };

bool pdep_in_use();                   // whether Encoder::best means pdep in this build
std::string encoder_name(Encoder e);  // "BMI2 pdep" or "portable shifts and masks"

// The map from the bounding box to the unit box at a depth.
struct KeyFrame {
    int dim = 2;
    int depth = 32;
    double lo[3] = {0, 0, 0};
    double scale[3] = {0, 0, 0};  // 1 / extent, 0 for a flat axis
};

// The bounding box of the vertices (parallel min/max). `depth` in 1..max_depth(m.dim).
KeyFrame key_frame(const mesh::MeshView& m, int depth);

// Element e's centroid in the unit box, every coordinate clamped to [0, 1).
inline void unit_position(const mesh::MeshView& m, const KeyFrame& f, std::size_t e, double* t) {
    const int k = m.dim + 1;
    const std::uint32_t* c = m.conn + e * static_cast<std::size_t>(k);
    const double* axes[3] = {m.x, m.y, m.z};
    const double inv = 1.0 / k;
    for (int a = 0; a < m.dim; ++a) {
        const double* p = axes[a];
        double sum = p[c[0]] + p[c[1]] + p[c[2]];
        if (k == 4) sum += p[c[3]];
        const double u = (sum * inv - f.lo[a]) * f.scale[a];
        t[a] = u < 0 ? 0 : (u < 1 ? u : 0x1.fffffffffffffp-1);
    }
}

// keys[e] for every element.
void compute_keys(const mesh::MeshView& m, const KeyFrame& f, Curve c, std::uint64_t* keys,
                  Encoder enc = Encoder::best);

// One element's key, computed on its own (for checks).
std::uint64_t element_key(const mesh::MeshView& m, const KeyFrame& f, Curve c, std::size_t e, Encoder enc);

}  // namespace suite::sfc
