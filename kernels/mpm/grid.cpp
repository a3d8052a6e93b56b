// The background grid: shape function coefficients, face neighbours, wall flags and each
// element's position along the Hilbert curve, computed once from the mesh.
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numeric>

#include "harness/common/units.hpp"
#include "kernels/mpm/mpm.hpp"
#include "kernels/sfc/keys.hpp"

namespace suite::mpm {

double Material::wave_speed() const {
    if (model == Model::fluid) return sound_speed;
    return std::sqrt(young * (1 - poisson) / ((1 + poisson) * (1 - 2 * poisson) * density));
}

namespace {

// The viscous limit of an explicit step, ρ0 l² / (6 η) (diffusion in three dimensions); none for a solid.
double viscous_step(const Grid& g, const Material& m) {
    if (m.model != Material::Model::fluid || !(m.viscosity > 0)) return std::numeric_limits<double>::infinity();
    return m.density * g.min_length * g.min_length / (6 * m.viscosity);
}

}  // namespace

double critical_step(const Grid& g, const Material& m) {
    return std::min(g.min_length / m.wave_speed(), viscous_step(g, m));
}

double next_step(const State& st) {
    const Settings& s = st.settings;
    if (s.dt > 0) return s.dt;
    const Material& m = s.material;
    if (m.model != Material::Model::fluid) return s.courant * critical_step(st.grid, m);
    // The fastest particle: information moves at c + |v| through the grid.
    const Particles& p = st.particles;
    const std::int64_t np = static_cast<std::int64_t>(p.size());
    double v2 = 0;
#pragma omp parallel for schedule(static) reduction(max : v2)
    for (std::int64_t i = 0; i < np; ++i) v2 = std::max(v2, p.vx[i] * p.vx[i] + p.vy[i] * p.vy[i] + p.vz[i] * p.vz[i]);
    return s.courant * std::min(st.grid.min_length / (m.sound_speed + std::sqrt(v2)), viscous_step(st.grid, m));
}

namespace {

// The shape functions of element e: λ = J⁻¹ (x - X0) for corners 1..3 with J = [X1-X0, X2-X0,
// X3-X0], λ0 = 1 - λ1 - λ2 - λ3. Returns false for a flat element.
bool shape_of(const mesh::Mesh& m, std::size_t e, double* s) {
    const std::uint32_t* c = &m.conn[4 * e];
    double j[3][3];
    for (int k = 0; k < 3; ++k) {
        j[0][k] = m.x[c[k + 1]] - m.x[c[0]];
        j[1][k] = m.y[c[k + 1]] - m.y[c[0]];
        j[2][k] = m.z[c[k + 1]] - m.z[c[0]];
    }
    const double det = j[0][0] * (j[1][1] * j[2][2] - j[1][2] * j[2][1]) -
                       j[0][1] * (j[1][0] * j[2][2] - j[1][2] * j[2][0]) +
                       j[0][2] * (j[1][0] * j[2][1] - j[1][1] * j[2][0]);
    if (mesh::degenerate(m.view(), e)) return false;
    // Rows of the inverse: the gradients of λ1, λ2, λ3.
    double inv[3][3];
    for (int r = 0; r < 3; ++r)
        for (int k = 0; k < 3; ++k) {
            const int r1 = (k + 1) % 3, r2 = (k + 2) % 3, c1 = (r + 1) % 3, c2 = (r + 2) % 3;
            inv[r][k] = (j[r1][c1] * j[r2][c2] - j[r1][c2] * j[r2][c1]) / det;
        }
    const double x0[3] = {m.x[c[0]], m.y[c[0]], m.z[c[0]]};
    double a0 = 1, g0[3] = {0, 0, 0};
    for (int i = 1; i < 4; ++i) {
        double* si = s + 4 * i;
        si[1] = inv[i - 1][0];
        si[2] = inv[i - 1][1];
        si[3] = inv[i - 1][2];
        si[0] = -(si[1] * x0[0] + si[2] * x0[1] + si[3] * x0[2]);
        a0 -= si[0];
        for (int k = 0; k < 3; ++k) g0[k] -= si[1 + k];
    }
    s[0] = a0;
    s[1] = g0[0];
    s[2] = g0[1];
    s[3] = g0[2];
    return true;
}

// Face neighbours: faces keyed by their sorted corners, matched in pairs after a sort.
std::vector<std::int32_t> neighbours(const mesh::Mesh& m) {
    struct Face {
        std::array<std::uint32_t, 3> key;
        std::uint32_t slot;  // 4 e + the corner the face is opposite
    };
    const std::size_t ne = m.elements();
    std::vector<Face> faces(4 * ne);
#pragma omp parallel for schedule(static)
    for (std::size_t e = 0; e < ne; ++e)
        for (int i = 0; i < 4; ++i) {
            std::array<std::uint32_t, 3> k{};
            for (int j = 0, n = 0; j < 4; ++j)
                if (j != i) k[n++] = m.conn[4 * e + j];
            std::sort(k.begin(), k.end());
            faces[4 * e + i] = {k, static_cast<std::uint32_t>(4 * e + i)};
        }
    std::sort(faces.begin(), faces.end(),
              [](const Face& a, const Face& b) { return a.key < b.key || (a.key == b.key && a.slot < b.slot); });
    std::vector<std::int32_t> out(4 * ne, -1);
    for (std::size_t f = 0; f + 1 < faces.size(); ++f)
        if (faces[f].key == faces[f + 1].key) {
            if (f + 2 < faces.size() && faces[f + 2].key == faces[f].key)
                throw UsageError("mesh is not a valid tetrahedral mesh: a face is shared by more than two tetrahedra");
            out[faces[f].slot] = static_cast<std::int32_t>(faces[f + 1].slot / 4);
            out[faces[f + 1].slot] = static_cast<std::int32_t>(faces[f].slot / 4);
            ++f;
        }
    return out;
}

}  // namespace

Grid make_grid(mesh::Mesh m) {
    if (m.dim != 3)
        throw UsageError(
            "the MPM background grid must be tetrahedral (a 3D mesh, e.g. box:NX,NY,NZ); this mesh has triangles");
    Grid g;
    const std::size_t ne = m.elements(), nv = m.vertices();
    g.shape.resize(16 * ne);
    double lo[3] = {std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
                    std::numeric_limits<double>::infinity()};
    double hi[3] = {-lo[0], -lo[1], -lo[2]};
    const std::vector<double>* axes[3] = {&m.x, &m.y, &m.z};
    for (int a = 0; a < 3; ++a)
        for (double v : *axes[a]) {
            lo[a] = std::min(lo[a], v);
            hi[a] = std::max(hi[a], v);
        }
    bool flat = false;
    double min_length = std::numeric_limits<double>::infinity();
#pragma omp parallel for schedule(static) reduction(|| : flat) reduction(min : min_length)
    for (std::size_t e = 0; e < ne; ++e) {
        double* s = &g.shape[16 * e];
        if (!shape_of(m, e, s)) {
            flat = true;
            continue;
        }
        // |∇λ_i| = 1 / (the altitude from corner i).
        for (int i = 0; i < 4; ++i)
            min_length = std::min(min_length, 1 / std::sqrt(s[4 * i + 1] * s[4 * i + 1] + s[4 * i + 2] * s[4 * i + 2] +
                                                            s[4 * i + 3] * s[4 * i + 3]));
    }
    if (flat)
        throw UsageError("the MPM background grid has a flat or degenerate tetrahedron; give a valid tetrahedral mesh");
    g.min_length = min_length;
    g.neighbour = neighbours(m);
    g.wall.assign(nv, 0);
    for (int a = 0; a < 3; ++a) {
        g.lo[a] = lo[a];
        g.hi[a] = hi[a];
        const double eps = 1e-12 * (hi[a] - lo[a]);
        for (std::size_t v = 0; v < nv; ++v)
            if ((*axes[a])[v] <= lo[a] + eps || (*axes[a])[v] >= hi[a] - eps)
                g.wall[v] |= static_cast<std::uint8_t>(1u << a);
    }
    // Each element's rank along the Hilbert curve of its centroid (particle sorting and the
    // active renumbering follow it, whatever the grid's own order).
    std::vector<std::uint64_t> keys(ne);
    const sfc::KeyFrame frame = sfc::key_frame(m.view(), 21);
    sfc::compute_keys(m.view(), frame, sfc::Curve::hilbert, keys.data());
    std::vector<std::uint32_t> by_key(ne);
    std::iota(by_key.begin(), by_key.end(), 0u);
    std::sort(by_key.begin(), by_key.end(),
              [&](std::uint32_t a, std::uint32_t b) { return keys[a] < keys[b] || (keys[a] == keys[b] && a < b); });
    g.curve.resize(ne);
    for (std::size_t r = 0; r < ne; ++r) g.curve[by_key[r]] = static_cast<std::uint32_t>(r);
    g.mesh = std::move(m);
    return g;
}

}  // namespace suite::mpm
