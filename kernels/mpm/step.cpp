// The phases of one explicit MPM step (mpm.hpp has the equations). Every particle loop runs on
// static blocks of particles (blocks.hpp), the split the state's first touch used.
#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <vector>

#include "kernels/mpm/implicit.hpp"
#include "kernels/mpm/mpm.hpp"
#include "kernels/mpm/scatter.hpp"

namespace suite::mpm {

namespace {

// Zeroes the normal components (bits of `wall`) of a node's vector.
inline void clear_walls(std::uint8_t wall, double* v) {
    if (wall & 1) v[0] = 0;
    if (wall & 2) v[1] = 0;
    if (wall & 4) v[2] = 0;
}

}  // namespace

// Mixed integration: Σ V_p of each element's particles (0 for an empty one).
void sum_element_volumes(State& st) {
    Array<double>& sum = st.element_volume;
    const std::int64_t ne = static_cast<std::int64_t>(st.grid.elements());
    if (sum.size() != static_cast<std::size_t>(ne)) sum.resize(static_cast<std::size_t>(ne));
    double* const s = sum.data();
#pragma omp parallel for schedule(static)
    for (std::int64_t e = 0; e < ne; ++e) s[e] = 0;
    const Particles& pt = st.particles;
    const std::int64_t np = static_cast<std::int64_t>(pt.size());
#pragma omp parallel for schedule(static)
    for (std::int64_t p = 0; p < np; ++p)
        std::atomic_ref<double>(s[pt.elem[p]]).fetch_add(pt.volume[p], std::memory_order_relaxed);
}

void p2g(State& st) {
    NodeState* const nodes = st.nodes.data();
    const std::int64_t nn = st.node_hi;
#pragma omp parallel for schedule(static)
    for (std::int64_t n = 0; n < nn; ++n) nodes[n] = NodeState{};
    const Particles& pt = st.particles;
    const double* const shape = st.grid.shape.data();
    const double g[3] = {st.settings.gravity[0], st.settings.gravity[1], st.settings.gravity[2]};
    const bool mixed = st.settings.integration == Integration::mixed;
    if (mixed) sum_element_volumes(st);
    const double* const evol = st.element_volume.data();
    const std::int32_t* const nb = st.grid.neighbour.data();
    // c per corner: m, p (3), f (3).
    scatter<0, 7>(st, [&](std::size_t p, double* c) {
        double vol = pt.volume[p];
        if (mixed) vol *= volume_scale(pt.elem[p], shape, nb, evol);
        const double m = pt.mass[p];
        const double v[3] = {pt.vx[p], pt.vy[p], pt.vz[p]};
        const double sxx = pt.stress[0][p], syy = pt.stress[1][p], szz = pt.stress[2][p];
        const double sxy = pt.stress[3][p], syz = pt.stress[4][p], szx = pt.stress[5][p];
        const double* s = shape + 16 * static_cast<std::size_t>(pt.elem[p]);
        const double* w = &pt.w[4 * p];
        for (int i = 0; i < 4; ++i) {
            const double wm = w[i] * m, gx = s[4 * i + 1], gy = s[4 * i + 2], gz = s[4 * i + 3];
            double* ci = c + 7 * i;
            ci[0] = wm;
            ci[1] = wm * v[0];
            ci[2] = wm * v[1];
            ci[3] = wm * v[2];
            ci[4] = wm * g[0] - vol * (sxx * gx + sxy * gy + szx * gz);
            ci[5] = wm * g[1] - vol * (sxy * gx + syy * gy + syz * gz);
            ci[6] = wm * g[2] - vol * (szx * gx + syz * gy + szz * gz);
        }
    });
}

void update_grid(State& st) {
    NodeState* const nodes = st.nodes.data();
    const std::uint8_t* const wall = st.grid.wall.data();
    const double dt = st.dt, damping = st.settings.damping;
    const std::int64_t nn = st.node_hi;
#pragma omp parallel for schedule(static)
    for (std::int64_t n = 0; n < nn; ++n) {
        NodeState& s = nodes[n];
        if (!(s.m > 0)) continue;
        const double before[3] = {s.p[0], s.p[1], s.p[2]};
        for (int k = 0; k < 3; ++k) s.p[k] += dt * (s.f[k] - damping * s.p[k]);
        clear_walls(wall[n], s.p);
        // The force G2P gives the particles is the whole change of the nodal momentum, the walls'
        // reaction included: zeroing only p's normal part left the particles moving into the
        // wall while the grid did not, and the kinetic energy grew step after step.
        for (int k = 0; k < 3; ++k) s.f[k] = (s.p[k] - before[k]) / dt;
    }
}

void g2p(State& st) {
    const NodeState* const nodes = st.nodes.data();
    const std::uint32_t* const conn = st.grid.mesh.conn.data();
    Particles& pt = st.particles;
    const double dt = st.dt;
    const double lo[3] = {st.grid.lo[0], st.grid.lo[1], st.grid.lo[2]},
                 hi[3] = {st.grid.hi[0], st.grid.hi[1], st.grid.hi[2]};
    double* const pos[3] = {pt.x.data(), pt.y.data(), pt.z.data()};
    double* const vel[3] = {pt.vx.data(), pt.vy.data(), pt.vz.data()};
    const std::int64_t np = static_cast<std::int64_t>(pt.size());
    std::uint64_t clamped = 0;
#pragma omp parallel for schedule(static) reduction(+ : clamped)
    for (std::int64_t p = 0; p < np; ++p) {
        const std::uint32_t* corners = conn + 4 * static_cast<std::size_t>(pt.elem[p]);
        const double* w = &pt.w[4 * p];
        double a[3] = {0, 0, 0}, v[3] = {0, 0, 0};
        for (int i = 0; i < 4; ++i) {
            const NodeState& s = nodes[corners[i]];
            // A corner with no mass has w = 0 for every particle of the element.
            if (!(s.m > 0)) continue;
            const double wi = w[i] / s.m;
            for (int k = 0; k < 3; ++k) {
                a[k] += wi * s.f[k];
                v[k] += wi * s.p[k];
            }
        }
        bool out = false;
        for (int k = 0; k < 3; ++k) {
            vel[k][p] += dt * a[k];
            double x = pos[k][p] + dt * v[k];
            // The walls stop the nodes, but a particle between a wall node and an inner one
            // can still cross the wall by a little: it is put back on the wall.
            if (x < lo[k] || x > hi[k]) {
                x = std::clamp(x, lo[k], hi[k]);
                out = true;
            }
            pos[k][p] = x;
        }
        clamped += out ? 1 : 0;
    }
    st.clamped += clamped;
}

void update_stress(State& st) {
    NodeState* const nodes = st.nodes.data();
    const std::int64_t nn = st.node_hi;
#pragma omp parallel for schedule(static)
    for (std::int64_t n = 0; n < nn; ++n) nodes[n].p[0] = nodes[n].p[1] = nodes[n].p[2] = 0;
    Particles& pt = st.particles;
    scatter<1, 3>(st, [&](std::size_t p, double* c) {
        const double* w = &pt.w[4 * p];
        const double m = pt.mass[p];
        for (int i = 0; i < 4; ++i) {
            c[3 * i] = w[i] * m * pt.vx[p];
            c[3 * i + 1] = w[i] * m * pt.vy[p];
            c[3 * i + 2] = w[i] * m * pt.vz[p];
        }
    });
    const std::uint8_t* const wall = st.grid.wall.data();
#pragma omp parallel for schedule(static)
    for (std::int64_t n = 0; n < nn; ++n) {
        NodeState& s = nodes[n];
        if (!(s.m > 0)) continue;
        for (int k = 0; k < 3; ++k) s.p[k] /= s.m;  // now the nodal velocity
        clear_walls(wall[n], s.p);
    }
    const Material& mat = st.settings.material;
    const bool fluid = mat.model == Material::Model::fluid;
    const double lambda = mat.young * mat.poisson / ((1 + mat.poisson) * (1 - 2 * mat.poisson));
    const double mu = mat.young / (2 * (1 + mat.poisson));
    const double bulk = mat.bulk_modulus(), eta = mat.viscosity, rho0 = mat.density;
    const double dt = st.dt;
    const std::uint32_t* const conn = st.grid.mesh.conn.data();
    const double* const shape = st.grid.shape.data();
    const std::int64_t np = static_cast<std::int64_t>(pt.size());
#pragma omp parallel for schedule(static)
    for (std::int64_t p = 0; p < np; ++p) {
        const std::size_t e = pt.elem[p];
        const std::uint32_t* corners = conn + 4 * e;
        const double* s = shape + 16 * e;
        double l[3][3] = {};  // ∇v: l[a][b] = ∂v_a/∂x_b
        for (int i = 0; i < 4; ++i) {
            const double* v = nodes[corners[i]].p;
            for (int a = 0; a < 3; ++a)
                for (int b = 0; b < 3; ++b) l[a][b] += v[a] * s[4 * i + 1 + b];
        }
        double de[3][3], dw[3][3];
        for (int a = 0; a < 3; ++a)
            for (int b = 0; b < 3; ++b) {
                de[a][b] = 0.5 * dt * (l[a][b] + l[b][a]);
                dw[a][b] = 0.5 * dt * (l[a][b] - l[b][a]);
            }
        const double tr = de[0][0] + de[1][1] + de[2][2];
        pt.volume[p] *= 1 + tr;
        if (fluid) {
            // No history: the pressure from how far the particle is compressed, the viscous
            // stress from the rate of deformation D = Δε / dt.
            const double j = pt.volume[p] * rho0 / pt.mass[p];
            const double pressure = std::max(0.0, bulk * (1 / j - 1));
            const double mean = tr / 3, visc = 2 * eta / dt;
            pt.stress[0][p] = -pressure + visc * (de[0][0] - mean);
            pt.stress[1][p] = -pressure + visc * (de[1][1] - mean);
            pt.stress[2][p] = -pressure + visc * (de[2][2] - mean);
            pt.stress[3][p] = visc * de[0][1];
            pt.stress[4][p] = visc * de[1][2];
            pt.stress[5][p] = visc * de[2][0];
            continue;
        }
        double sg[3][3] = {{pt.stress[0][p], pt.stress[3][p], pt.stress[5][p]},
                           {pt.stress[3][p], pt.stress[1][p], pt.stress[4][p]},
                           {pt.stress[5][p], pt.stress[4][p], pt.stress[2][p]}};
        double out[3][3];
        for (int a = 0; a < 3; ++a)
            for (int b = 0; b < 3; ++b) {
                double rot = 0;  // (Δω σ - σ Δω)[a][b]
                for (int k = 0; k < 3; ++k) rot += dw[a][k] * sg[k][b] - sg[a][k] * dw[k][b];
                out[a][b] = sg[a][b] + 2 * mu * de[a][b] + (a == b ? lambda * tr : 0) + rot;
            }
        pt.stress[0][p] = out[0][0];
        pt.stress[1][p] = out[1][1];
        pt.stress[2][p] = out[2][2];
        pt.stress[3][p] = 0.5 * (out[0][1] + out[1][0]);
        pt.stress[4][p] = 0.5 * (out[1][2] + out[2][1]);
        pt.stress[5][p] = 0.5 * (out[2][0] + out[0][2]);
    }
}

void step(State& st) {
    if (st.settings.integrator != Integrator::explicit_step) {
        // Newmark and Newton (implicit.hpp); a failed step leaves the state where it was.
        implicit_step(st);
        if (!st.implicit.failure.empty()) return;
        st.dt_min = st.steps == 0 ? st.dt : std::min(st.dt_min, st.dt);
        st.dt_max = std::max(st.dt_max, st.dt);
        st.time += st.dt;
        ++st.steps;
        return;
    }
    // A fluid's step follows its fastest particle; an elastic material's is the same every step.
    if (st.settings.material.model == Material::Model::fluid) st.dt = next_step(st);
    st.dt_min = st.steps == 0 ? st.dt : std::min(st.dt_min, st.dt);
    st.dt_max = std::max(st.dt_max, st.dt);
    p2g(st);
    update_grid(st);
    g2p(st);
    update_stress(st);
    locate(st);
    st.time += st.dt;
    ++st.steps;
}

}  // namespace suite::mpm
