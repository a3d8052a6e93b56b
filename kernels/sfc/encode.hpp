#pragma once
// Space-filling-curve keys of one point, from its position t in the unit box [0,1)^dim
// (the mesh's bounding box mapped there). Everything here is inline and exact:
//   quantize:   q = floor(t * 2^depth), per axis
//   morton:     the bits of q interleaved, x in the lowest bit of each group of dim bits
//               (BMI2 pdep, or the portable shift-and-mask spreading; both give the same key)
//   hilbert:    Skilling's transform of q ("Programming the Hilbert curve", AIP 2004) to the
//               transposed Hilbert index, then interleaved with axis 0 as the highest bit
//   recursive:  the thesis's Algorithm 2: halve the box depth times, one bit per axis a level.
// The recursive form halves the *unit* box, where every midpoint is a dyadic number and so
// exact: it yields the same bits as quantize + interleave, which is what makes "identical
// keys" a property that holds rather than one that holds up to rounding.
#include <cstdint>

#if defined(__BMI2__)
#include <immintrin.h>
#endif

namespace suite::sfc {

// The deepest level a 64-bit key holds: 32 bits an axis in 2D, 21 in 3D.
constexpr int max_depth(int dim) { return dim == 2 ? 32 : 21; }

// t in [0, 1) per axis (callers clamp), to the cell index at `depth`.
inline std::uint32_t quantize(double t, int depth) {
    // 2^depth is a power of two: the product is exact, so floor gives exactly the first bits of t.
    return static_cast<std::uint32_t>(static_cast<std::uint64_t>(t * static_cast<double>(1ULL << depth)));
}

inline std::uint64_t spread2(std::uint64_t x) {  // bit i -> bit 2i, for 32 bits
    x &= 0xffffffffULL;
    x = (x | x << 16) & 0x0000ffff0000ffffULL;
    x = (x | x << 8) & 0x00ff00ff00ff00ffULL;
    x = (x | x << 4) & 0x0f0f0f0f0f0f0f0fULL;
    x = (x | x << 2) & 0x3333333333333333ULL;
    x = (x | x << 1) & 0x5555555555555555ULL;
    return x;
}
inline std::uint64_t spread3(std::uint64_t x) {  // bit i -> bit 3i, for 21 bits
    x &= 0x1fffffULL;
    x = (x | x << 32) & 0x001f00000000ffffULL;
    x = (x | x << 16) & 0x001f0000ff0000ffULL;
    x = (x | x << 8) & 0x100f00f00f00f00fULL;
    x = (x | x << 4) & 0x10c30c30c30c30c3ULL;
    x = (x | x << 2) & 0x1249249249249249ULL;
    return x;
}

template <int Dim>
inline std::uint64_t morton_portable(const std::uint32_t* q) {
    if constexpr (Dim == 2) return spread2(q[0]) | spread2(q[1]) << 1;
    else return spread3(q[0]) | spread3(q[1]) << 1 | spread3(q[2]) << 2;
}

#if defined(__BMI2__)
constexpr bool have_pdep = true;
template <int Dim>
inline std::uint64_t morton_pdep(const std::uint32_t* q) {
    if constexpr (Dim == 2) return _pdep_u64(q[0], 0x5555555555555555ULL) | _pdep_u64(q[1], 0xaaaaaaaaaaaaaaaaULL);
    else return _pdep_u64(q[0], 0x1249249249249249ULL) | _pdep_u64(q[1], 0x2492492492492492ULL) | _pdep_u64(q[2], 0x4924924924924924ULL);
}
#else
constexpr bool have_pdep = false;
template <int Dim>
inline std::uint64_t morton_pdep(const std::uint32_t* q) { return morton_portable<Dim>(q); }  // never chosen: have_pdep is false
#endif

// Skilling's AxestoTranspose on `depth`-bit coordinates, in place.
template <int Dim>
inline void hilbert_transpose(std::uint32_t* x, int depth) {
    const std::uint32_t top = 1u << (depth - 1);
    // Undo the excess work of the Gray code, level by level: where axis i has the level's bit,
    // invert the lower bits of axis 0, else exchange the lower bits of axes 0 and i. Written
    // with masks instead of branches: the bit is a coin toss, and a mispredicted branch per bit
    // would cost more than the arithmetic.
    for (std::uint32_t q = top; q > 1; q >>= 1) {
        const std::uint32_t p = q - 1;
        for (int i = 0; i < Dim; ++i) {
            const std::uint32_t set = 0u - ((x[i] & q) != 0);  // all ones when the bit is set
            const std::uint32_t t = (x[0] ^ x[i]) & p & ~set;
            x[0] ^= (p & set) | t;
            x[i] ^= t;
        }
    }
    for (int i = 1; i < Dim; ++i) x[i] ^= x[i - 1];  // Gray encode
    std::uint32_t t = 0;
    for (std::uint32_t q = top; q > 1; q >>= 1) t ^= (q - 1) & (0u - ((x[Dim - 1] & q) != 0));
    for (int i = 0; i < Dim; ++i) x[i] ^= t;
}

// The Hilbert key: the transposed index interleaved with axis 0 as the most significant bit of
// each level, which is the Morton interleave of the axes in reverse order.
template <int Dim, bool Pdep>
inline std::uint64_t hilbert_key(const std::uint32_t* q, int depth) {
    std::uint32_t x[3] = {q[0], q[1], Dim == 3 ? q[2] : 0};
    hilbert_transpose<Dim>(x, depth);
    const std::uint32_t r[3] = {x[Dim - 1], x[Dim - 2], Dim == 3 ? x[0] : 0};
    return Pdep ? morton_pdep<Dim>(r) : morton_portable<Dim>(r);
}

// The inverses, for checks: a key back to the cell it names. Written independently of the
// encoders (bit by bit, no masks, no pdep), so that decode(encode(q)) == q is a real test.
template <int Dim>
inline void morton_decode(std::uint64_t key, int depth, std::uint32_t* q) {
    for (int a = 0; a < Dim; ++a) q[a] = 0;
    for (int level = 0; level < depth; ++level)
        for (int a = 0; a < Dim; ++a) q[a] |= static_cast<std::uint32_t>((key >> (level * Dim + a)) & 1) << level;
}

// Skilling's TransposetoAxes after splitting the key into the transposed form.
template <int Dim>
inline void hilbert_decode(std::uint64_t key, int depth, std::uint32_t* q) {
    std::uint32_t x[3] = {0, 0, 0};
    for (int level = 0; level < depth; ++level)
        for (int i = 0; i < Dim; ++i) x[i] |= static_cast<std::uint32_t>((key >> (level * Dim + (Dim - 1 - i))) & 1) << level;
    const std::uint32_t n = depth == 32 ? 0 : 1u << depth;  // 2^depth; at 32 bits qb wraps to 0 after the top level
    std::uint32_t t = x[Dim - 1] >> 1;  // Gray decode by H ^ (H/2)
    for (int i = Dim - 1; i > 0; --i) x[i] ^= x[i - 1];
    x[0] ^= t;
    for (std::uint32_t qb = 2; qb != n; qb <<= 1) {  // undo the excess work
        const std::uint32_t p = qb - 1;
        for (int i = Dim - 1; i >= 0; --i) {
            if (x[i] & qb) {
                x[0] ^= p;
            } else {
                t = (x[0] ^ x[i]) & p;
                x[0] ^= t;
                x[i] ^= t;
            }
        }
    }
    for (int a = 0; a < Dim; ++a) q[a] = x[a];
}

// Algorithm 2 of the thesis: at each level halve the box along every axis and record on which
// side the point lies (1: upper half), x as the lowest bit of the level's group.
template <int Dim>
inline std::uint64_t morton_recursive(const double* t, int depth) {
    double lo[3] = {0, 0, 0}, hi[3] = {1, 1, 1};
    std::uint64_t key = 0;
    for (int level = 0; level < depth; ++level) {
        std::uint64_t bits = 0;
        for (int a = 0; a < Dim; ++a) {
            // Written as selects, not branches: the side is a coin toss for a mesh, and a
            // mispredicted branch per bit would measure the predictor, not the algorithm.
            const double mid = 0.5 * (lo[a] + hi[a]);
            const bool upper = t[a] >= mid;
            bits |= static_cast<std::uint64_t>(upper) << a;
            lo[a] = upper ? mid : lo[a];
            hi[a] = upper ? hi[a] : mid;
        }
        key = key << Dim | bits;
    }
    return key;
}

}  // namespace suite::sfc
