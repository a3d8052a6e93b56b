#pragma once
// Space-filling-curve keys of one point, from its position t in the unit box [0,1)^dim
// (the mesh's bounding box mapped there). Everything here is inline and exact:
//   quantize:   q = floor(t * 2^depth), per axis
//   morton:     the bits of q interleaved, x in the lowest bit of each group of dim bits
//               (BMI2 pdep, or the portable shift-and-mask spreading; both give the same key)
//   hilbert:    the Morton code of q read from the top, a few levels at a time, through a
//               table-driven state machine (4 states in 2D, 24 in 3D). The tables are built at
//               compile time from the defining transform, Skilling's ("Programming the Hilbert
//               curve", AIP 2004) transposed index interleaved with axis 0 as the highest bit,
//               which stays here as hilbert_key_reference for the tests.
//   recursive:  the thesis's Algorithm 2: halve the box depth times, one bit per axis a level.
// The recursive form halves the *unit* box, where every midpoint is a dyadic number and so
// exact: it yields the same bits as quantize + interleave, which is what makes "identical
// keys" a property that holds rather than one that holds up to rounding.
#include <array>
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

constexpr std::uint64_t spread2(std::uint64_t x) {  // bit i -> bit 2i, for 32 bits
    x &= 0xffffffffULL;
    x = (x | x << 16) & 0x0000ffff0000ffffULL;
    x = (x | x << 8) & 0x00ff00ff00ff00ffULL;
    x = (x | x << 4) & 0x0f0f0f0f0f0f0f0fULL;
    x = (x | x << 2) & 0x3333333333333333ULL;
    x = (x | x << 1) & 0x5555555555555555ULL;
    return x;
}
constexpr std::uint64_t spread3(std::uint64_t x) {  // bit i -> bit 3i, for 21 bits
    x &= 0x1fffffULL;
    x = (x | x << 32) & 0x001f00000000ffffULL;
    x = (x | x << 16) & 0x001f0000ff0000ffULL;
    x = (x | x << 8) & 0x100f00f00f00f00fULL;
    x = (x | x << 4) & 0x10c30c30c30c30c3ULL;
    x = (x | x << 2) & 0x1249249249249249ULL;
    return x;
}

template <int Dim>
constexpr std::uint64_t morton_portable(const std::uint32_t* q) {
    if constexpr (Dim == 2)
        return spread2(q[0]) | spread2(q[1]) << 1;
    else
        return spread3(q[0]) | spread3(q[1]) << 1 | spread3(q[2]) << 2;
}

#if defined(__BMI2__)
constexpr bool have_pdep = true;
template <int Dim>
inline std::uint64_t morton_pdep(const std::uint32_t* q) {
    if constexpr (Dim == 2)
        return _pdep_u64(q[0], 0x5555555555555555ULL) | _pdep_u64(q[1], 0xaaaaaaaaaaaaaaaaULL);
    else
        return _pdep_u64(q[0], 0x1249249249249249ULL) | _pdep_u64(q[1], 0x2492492492492492ULL) |
               _pdep_u64(q[2], 0x4924924924924924ULL);
}
#else
constexpr bool have_pdep = false;
template <int Dim>
inline std::uint64_t morton_pdep(const std::uint32_t* q) {
    return morton_portable<Dim>(q);
}  // never chosen: have_pdep is false
#endif

// Skilling's AxestoTranspose on `depth`-bit coordinates, in place.
template <int Dim>
constexpr void hilbert_transpose(std::uint32_t* x, int depth) {
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

// The Hilbert key by its definition: the transposed index interleaved with axis 0 as the most
// significant bit of each level, which is the Morton interleave of the axes in reverse order.
// About 15x slower than Morton; the tables below are built from it and the tests hold the
// fast key to it.
template <int Dim>
constexpr std::uint64_t hilbert_key_reference(const std::uint32_t* q, int depth) {
    std::uint32_t x[3] = {q[0], q[1], Dim == 3 ? q[2] : 0};
    hilbert_transpose<Dim>(x, depth);
    const std::uint32_t r[3] = {x[Dim - 1], x[Dim - 2], Dim == 3 ? x[0] : 0};
    return morton_portable<Dim>(r);
}

// The Hilbert curve as a finite state machine. Inside any cell the curve visits the 2^Dim
// children in one of a few orders (a state); which child comes when, and the state inside each
// child, depend only on the state. Two facts about the transform make that a machine:
//   - a key's top levels depend only on the cell's top levels (the transform only ever changes
//     bits below the one it tests), so key_d(q) == key_D(q << (D - d)) >> ((D - d) * Dim);
//   - the curve inside a cell is the curve under a symmetry of the cube, so the order of its
//     children at the next two levels names its state. (This one is the construction's idea
//     rather than a line of the code: the tests hold the tables' keys to the reference's at
//     every depth, and a wrongly merged state would fail them.)
// The machine is found by walking the reference key from the whole box down, one level at a
// time, naming each cell's state by that two-level order. Then `levels` levels are folded into
// one lookup: the index is a state and Levels*Dim Morton bits, the entry the Levels*Dim key
// bits and the next state. 2D: 4 states x 256 entries (2 KiB), 8 lookups for 32 levels; 3D: 24
// states x 512 entries (24 KiB, L1-resident), 7 lookups for 21 levels.
namespace hilbert_detail {

template <int Dim>
struct OneLevel {
    static constexpr int children = 1 << Dim;
    static constexpr int max_states = 48;  // the symmetries of the cube bound it; 2D uses 4, 3D 24
    int states = 0;
    std::array<std::array<std::uint8_t, children>, max_states> digit{};         // child -> its place in the order
    std::array<std::array<std::uint8_t, children>, max_states> next{};          // child -> the state inside it
    std::array<std::array<std::uint8_t, (1 << (2 * Dim))>, max_states> name{};  // the two-level order
};

// The order of the children and grandchildren of the cell `prefix` (its top `level` bits per
// axis): the last two levels of the reference keys at depth level + 2, which by the first fact
// are the same bits as at full depth.
template <int Dim>
constexpr std::array<std::uint8_t, (1 << (2 * Dim))> two_level_order(const std::uint32_t* prefix, int level) {
    std::array<std::uint8_t, (1 << (2 * Dim))> order{};
    for (int c = 0; c < (1 << (2 * Dim)); ++c) {
        std::uint32_t q[3] = {0, 0, 0};
        for (int a = 0; a < Dim; ++a) q[a] = prefix[a] << 2 | ((c >> a) & 1) << 1 | ((c >> (Dim + a)) & 1);
        order[c] = static_cast<std::uint8_t>(hilbert_key_reference<Dim>(q, level + 2) & ((1u << (2 * Dim)) - 1));
    }
    return order;
}

template <int Dim>
constexpr OneLevel<Dim> discover() {
    constexpr int depth = max_depth(Dim);
    constexpr int n = 1 << Dim;
    using Order = std::array<std::uint8_t, (1 << (2 * Dim))>;
    OneLevel<Dim> m;
    auto& name = m.name;
    std::array<std::array<std::uint32_t, 3>, OneLevel<Dim>::max_states> prefix{};
    std::array<int, OneLevel<Dim>::max_states> level{};
    name[0] = two_level_order<Dim>(prefix[0].data(), 0);
    m.states = 1;
    for (int s = 0; s < m.states; ++s) {  // breadth first: every state is met within a few levels
        if (level[s] + 3 > depth) throw "hilbert tables: a state first met too deep to name";
        for (int child = 0; child < n; ++child) {
            std::array<std::uint32_t, 3> p{};
            for (int a = 0; a < Dim; ++a) p[a] = prefix[s][a] << 1 | ((child >> a) & 1);
            m.digit[s][child] = static_cast<std::uint8_t>(hilbert_key_reference<Dim>(p.data(), level[s] + 1) & (n - 1));
            const Order o = two_level_order<Dim>(p.data(), level[s] + 1);
            int t = 0;
            while (t < m.states && name[t] != o) ++t;
            if (t == m.states) {
                if (t == OneLevel<Dim>::max_states) throw "hilbert tables: more states than the cube has symmetries";
                name[t] = o;
                prefix[t] = p;
                level[t] = level[s] + 1;
                ++m.states;
            }
            m.next[s][child] = static_cast<std::uint8_t>(t);
        }
    }
    return m;
}

template <int Dim>
inline constexpr OneLevel<Dim> one_level = discover<Dim>();

}  // namespace hilbert_detail

template <int Dim>
struct HilbertTables {
    static constexpr int levels = Dim == 2 ? 4 : 3;  // per lookup; both divide max_depth
    static constexpr int bits = levels * Dim;        // key bits per lookup: 8 or 9
    static constexpr std::uint32_t mask = (1u << bits) - 1;
    static constexpr int states = hilbert_detail::one_level<Dim>.states;
    static constexpr int lookups = max_depth(Dim) / levels;
    static_assert(max_depth(Dim) % levels == 0);
    static_assert(states << bits <= 1 << 16, "an entry packs the next state's offset into 16 bits");
    // step[state << bits | chunk]: the chunk's key bits | (next state << bits), so the entry
    // with its key bits cleared is the next lookup's base.
    std::array<std::uint16_t, (states << bits)> step{};
    // start[lookups - c]: the base where a key of c chunks (depth c * levels) starts.
    std::array<std::uint16_t, lookups> start{};
};

template <int Dim>
constexpr HilbertTables<Dim> build_hilbert_tables() {
    using T = HilbertTables<Dim>;
    const auto& one = hilbert_detail::one_level<Dim>;
    T t;
    for (int s = 0; s < T::states; ++s) {
        for (std::uint32_t chunk = 0; chunk <= T::mask; ++chunk) {
            int state = s;
            std::uint32_t digits = 0;
            for (int l = T::levels - 1; l >= 0; --l) {  // the chunk's top level first
                const int child = (chunk >> (l * Dim)) & ((1 << Dim) - 1);
                digits = digits << Dim | one.digit[state][child];
                state = one.next[state][child];
            }
            t.step[static_cast<std::size_t>(s) << T::bits | chunk] =
                static_cast<std::uint16_t>(digits | static_cast<std::uint32_t>(state) << T::bits);
        }
    }
    // The whole box of a curve of depth d is itself one of the states (the curve is the same
    // shape at every depth, up to a symmetry that can depend on d): found by its name.
    for (int chunks = 1; chunks <= T::lookups; ++chunks) {
        const int depth = chunks * T::levels;
        std::array<std::uint8_t, (1 << (2 * Dim))> order{};
        for (int c = 0; c < (1 << (2 * Dim)); ++c) {
            std::uint32_t q[3] = {0, 0, 0};
            for (int a = 0; a < Dim; ++a) q[a] = (((c >> a) & 1u) << 1 | ((c >> (Dim + a)) & 1u)) << (depth - 2);
            order[c] = static_cast<std::uint8_t>(hilbert_key_reference<Dim>(q, depth) >> ((depth - 2) * Dim));
        }
        int s = 0;
        while (s < T::states && one.name[s] != order) ++s;
        if (s == T::states) throw "hilbert tables: the whole box of a curve is not one of the states";
        t.start[T::lookups - chunks] = static_cast<std::uint16_t>(s << T::bits);
    }
    return t;
}

template <int Dim>
inline constexpr HilbertTables<Dim> hilbert_tables = build_hilbert_tables<Dim>();

// The Hilbert key from the cell's Morton code (same depth): a chain of table lookups from the
// top. Depths that are not a multiple of the lookup's levels are padded below with zeros and the
// padding's key bits shifted off (the first fact above).
template <int Dim>
inline std::uint64_t hilbert_from_morton(std::uint64_t morton, int depth) {
    using T = HilbertTables<Dim>;
    const auto& t = hilbert_tables<Dim>;
    const int chunks = (depth + T::levels - 1) / T::levels;
    const int pad = chunks * T::levels - depth;
    morton <<= pad * Dim;
    std::uint32_t base = t.start[T::lookups - chunks];
    std::uint64_t key = 0;
    for (int j = chunks - 1; j >= 0; --j) {
        const std::uint32_t e = t.step[base | static_cast<std::uint32_t>(morton >> (j * T::bits) & T::mask)];
        key = key << T::bits | (e & T::mask);
        base = e & ~T::mask;
    }
    return key >> (pad * Dim);
}

// hilbert_from_morton on n keys in place. Each lookup waits for the one before it in its own
// key, so the keys are walked four at a time in lock step: four independent chains for the core
// to overlap. (Measured on the VM: 8 lanes spill registers and are slower; a trip count fixed at
// full depth lets the compiler unroll and vectorise the lanes, and is slower too.)
template <int Dim>
inline void hilbert_from_morton_run(std::uint64_t* keys, std::size_t n, int depth) {
    using T = HilbertTables<Dim>;
    const auto& t = hilbert_tables<Dim>;
    constexpr int lanes = 4;
    const int chunks = (depth + T::levels - 1) / T::levels;
    const int pad = chunks * T::levels - depth;
    std::size_t i = 0;
    for (; i + lanes <= n; i += lanes) {
        std::uint64_t m[lanes], key[lanes] = {};
        std::uint32_t base[lanes];
        for (int l = 0; l < lanes; ++l) {
            m[l] = keys[i + l] << (pad * Dim);
            base[l] = t.start[T::lookups - chunks];
        }
        for (int j = chunks - 1; j >= 0; --j) {
            for (int l = 0; l < lanes; ++l) {
                const std::uint32_t e = t.step[base[l] | static_cast<std::uint32_t>(m[l] >> (j * T::bits) & T::mask)];
                key[l] = key[l] << T::bits | (e & T::mask);
                base[l] = e & ~T::mask;
            }
        }
        for (int l = 0; l < lanes; ++l) keys[i + l] = key[l] >> (pad * Dim);
    }
    for (; i < n; ++i) keys[i] = hilbert_from_morton<Dim>(keys[i], depth);
}

template <int Dim, bool Pdep>
inline std::uint64_t hilbert_key(const std::uint32_t* q, int depth) {
    return hilbert_from_morton<Dim>(Pdep ? morton_pdep<Dim>(q) : morton_portable<Dim>(q), depth);
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
        for (int i = 0; i < Dim; ++i)
            x[i] |= static_cast<std::uint32_t>((key >> (level * Dim + (Dim - 1 - i))) & 1) << level;
    const std::uint32_t n = depth == 32 ? 0 : 1u << depth;  // 2^depth; at 32 bits qb wraps to 0 after the top level
    std::uint32_t t = x[Dim - 1] >> 1;                      // Gray decode by H ^ (H/2)
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
