#include "kernels/sfc/keys.hpp"

#include <omp.h>

#include <algorithm>
#include <limits>

#include "harness/kernel/blocks.hpp"

namespace suite::sfc {

namespace {

template <int Dim, Curve C, bool Pdep>
inline std::uint64_t key_of(const mesh::MeshView& m, const KeyFrame& f, std::size_t e) {
    double t[3];
    unit_position(m, f, e, t);
    if constexpr (C == Curve::morton_recursive) {
        return morton_recursive<Dim>(t, f.depth);
    } else {
        std::uint32_t q[3];
        for (int a = 0; a < Dim; ++a) q[a] = quantize(t[a], f.depth);
        if constexpr (C == Curve::morton)
            return Pdep ? morton_pdep<Dim>(q) : morton_portable<Dim>(q);
        else
            return hilbert_key<Dim, Pdep>(q, f.depth);
    }
}

template <int Dim, Curve C, bool Pdep>
void keys_loop(const mesh::MeshView& m, const KeyFrame& f, std::uint64_t* keys) {
    const std::int64_t ne = static_cast<std::int64_t>(m.elements);
#pragma omp parallel
    {
        const Block b = my_block(ne);
        // The corners' coordinates are gathered from anywhere in the vertex arrays; asking for
        // those of the element 16 ahead keeps several misses in flight (1.3-1.6x on the VM).
        constexpr std::int64_t ahead = 16;
        for (std::int64_t e = b.lo; e < b.hi; ++e) {
            if (e + ahead < b.hi) {
                const std::uint32_t* c = m.conn + (e + ahead) * (Dim + 1);
                for (int j = 0; j <= Dim; ++j) {
                    __builtin_prefetch(m.x + c[j]);
                    __builtin_prefetch(m.y + c[j]);
                    if (Dim == 3) __builtin_prefetch(m.z + c[j]);
                }
            }
            // Hilbert: the Morton code here, turned into the Hilbert key below.
            keys[e] = key_of < Dim, C == Curve::hilbert ? Curve::morton : C, Pdep > (m, f, static_cast<std::size_t>(e));
        }
        // The table walk is a chain of dependent loads per key. Kept apart from the gathers, it
        // is a loop of independent chains that the core overlaps (see hilbert_from_morton_run).
        if constexpr (C == Curve::hilbert)
            if (b.hi > b.lo) hilbert_from_morton_run<Dim>(keys + b.lo, static_cast<std::size_t>(b.hi - b.lo), f.depth);
    }
}

template <int Dim>
void dispatch(const mesh::MeshView& m, const KeyFrame& f, Curve c, std::uint64_t* keys, bool pdep) {
    switch (c) {
        case Curve::morton:
            return pdep ? keys_loop<Dim, Curve::morton, true>(m, f, keys)
                        : keys_loop<Dim, Curve::morton, false>(m, f, keys);
        case Curve::hilbert:
            return pdep ? keys_loop<Dim, Curve::hilbert, true>(m, f, keys)
                        : keys_loop<Dim, Curve::hilbert, false>(m, f, keys);
        case Curve::morton_recursive:
            return keys_loop<Dim, Curve::morton_recursive, false>(m, f, keys);
    }
}

}  // namespace

bool pdep_in_use() { return have_pdep; }

std::string encoder_name(Encoder e) {
    return e == Encoder::best && have_pdep ? "BMI2 pdep" : "portable shifts and masks";
}

KeyFrame key_frame(const mesh::MeshView& m, int depth) {
    KeyFrame f;
    f.dim = m.dim;
    f.depth = depth;
    const double* axes[3] = {m.x, m.y, m.z};
    const std::int64_t nv = static_cast<std::int64_t>(m.vertices);
    for (int a = 0; a < m.dim; ++a) {
        const double* p = axes[a];
        double lo = std::numeric_limits<double>::infinity(), hi = -lo;
#pragma omp parallel for schedule(static) reduction(min : lo) reduction(max : hi)
        for (std::int64_t v = 0; v < nv; ++v) {
            lo = std::min(lo, p[v]);
            hi = std::max(hi, p[v]);
        }
        f.lo[a] = lo;
        f.scale[a] = hi > lo ? 1.0 / (hi - lo) : 0.0;
    }
    return f;
}

void compute_keys(const mesh::MeshView& m, const KeyFrame& f, Curve c, std::uint64_t* keys, Encoder enc) {
    const bool pdep = enc == Encoder::best && have_pdep;
    m.dim == 2 ? dispatch<2>(m, f, c, keys, pdep) : dispatch<3>(m, f, c, keys, pdep);
}

std::uint64_t element_key(const mesh::MeshView& m, const KeyFrame& f, Curve c, std::size_t e, Encoder enc) {
    const bool pdep = enc == Encoder::best && have_pdep;
    auto one = [&]<int Dim>() -> std::uint64_t {
        switch (c) {
            case Curve::morton:
                return pdep ? key_of<Dim, Curve::morton, true>(m, f, e) : key_of<Dim, Curve::morton, false>(m, f, e);
            case Curve::hilbert:
                return pdep ? key_of<Dim, Curve::hilbert, true>(m, f, e) : key_of<Dim, Curve::hilbert, false>(m, f, e);
            case Curve::morton_recursive:
                return key_of<Dim, Curve::morton_recursive, false>(m, f, e);
        }
        return 0;
    };
    return m.dim == 2 ? one.template operator()<2>() : one.template operator()<3>();
}

}  // namespace suite::sfc
