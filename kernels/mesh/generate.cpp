// The disk and box generators; see generate.hpp.
#include <cmath>
#include <numbers>

#include "kernels/mesh/generate.hpp"

namespace suite::mesh {

Mesh disk_mesh(int refine) {
    Mesh m;
    m.dim = 2;
    m.x.push_back(0);
    m.y.push_back(0);
    for (int i = 0; i < 6; ++i) {
        m.x.push_back(std::cos(i * std::numbers::pi / 3));
        m.y.push_back(std::sin(i * std::numbers::pi / 3));
    }
    for (std::uint32_t i = 0; i < 6; ++i) m.conn.insert(m.conn.end(), {0u, 1 + i, 1 + (i + 1) % 6});
    for (int r = 0; r < refine; ++r) m = refine_uniform(m);
    // In the direction theta the hexagon's boundary is at cos(30 deg) / cos(phi - 30 deg), phi the
    // angle within theta's 60-degree sector; dividing by it puts that boundary on the circle.
    const double sector = std::numbers::pi / 3;
    const std::int64_t nv = static_cast<std::int64_t>(m.vertices());
#pragma omp parallel for schedule(static)
    for (std::int64_t v = 0; v < nv; ++v) {
        if (m.x[v] == 0 && m.y[v] == 0) continue;
        double phi = std::fmod(std::atan2(m.y[v], m.x[v]) + 2 * std::numbers::pi, sector);
        const double boundary = std::cos(sector / 2) / std::cos(phi - sector / 2);
        m.x[v] /= boundary;
        m.y[v] /= boundary;
    }
    return m;
}

Mesh box_mesh(std::uint32_t nx, std::uint32_t ny, std::uint32_t nz) {
    Mesh m;
    m.dim = 3;
    const std::uint64_t px = nx + 1ULL, py = ny + 1ULL, pz = nz + 1ULL;
    m.x.resize(px * py * pz);
    m.y.resize(m.x.size());
    m.z.resize(m.x.size());
    const std::int64_t npz = static_cast<std::int64_t>(pz);
#pragma omp parallel for schedule(static)
    for (std::int64_t k = 0; k < npz; ++k)
        for (std::uint64_t j = 0; j < py; ++j)
            for (std::uint64_t i = 0; i < px; ++i) {
                const std::uint64_t v = i + px * (j + py * static_cast<std::uint64_t>(k));
                m.x[v] = static_cast<double>(i) / nx;
                m.y[v] = static_cast<double>(j) / ny;
                m.z[v] = static_cast<double>(k) / nz;
            }
    // The 6 monotone paths from corner (0,0,0) to (1,1,1), one per order of the axes; an odd
    // order would give a negatively oriented tetrahedron, so its last two corners are swapped.
    static const int order[6][3] = {{0, 1, 2}, {1, 2, 0}, {2, 0, 1}, {0, 2, 1}, {2, 1, 0}, {1, 0, 2}};
    m.conn.resize(24ULL * nx * ny * nz);
    const std::int64_t cubes = static_cast<std::int64_t>(nx) * ny * nz;
#pragma omp parallel for schedule(static)
    for (std::int64_t c = 0; c < cubes; ++c) {
        const std::uint64_t i = static_cast<std::uint64_t>(c) % nx, j = static_cast<std::uint64_t>(c) / nx % ny,
                            k = static_cast<std::uint64_t>(c) / nx / ny;
        std::uint32_t* out = m.conn.data() + 24 * c;
        for (int t = 0; t < 6; ++t) {
            std::uint64_t at[3] = {i, j, k};
            std::uint32_t corner[4];
            corner[0] = static_cast<std::uint32_t>(at[0] + px * (at[1] + py * at[2]));
            for (int s = 0; s < 3; ++s) {
                ++at[order[t][s]];
                corner[s + 1] = static_cast<std::uint32_t>(at[0] + px * (at[1] + py * at[2]));
            }
            if (t >= 3) std::swap(corner[2], corner[3]);
            std::copy(corner, corner + 4, out + 4 * t);
        }
    }
    return m;
}

}  // namespace suite::mesh
