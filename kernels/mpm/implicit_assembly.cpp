// The internal force and its tangent on the active system (implicit.hpp has the equations):
// every particle's 12 force entries and 12 x 12 tangent entries, computed where it lies and
// added into the rows of its element's corners. How the threads avoid racing on a row is the
// state's scatter strategy, as for P2G (mpm.hpp):
//   serial     one thread, particles in order
//   atomic     particles in static blocks, every addition an atomic add
//   colour     one colour of elements at a time (no two share a node, so no two share a row),
//              each element's particles (the bins) added without synchronisation
//   partition  the element runs of the projection's partition scatter (balanced by particles,
//              contiguous along the grid's order); rows of a node no other run touches added
//              directly, rows of a shared node atomically
#include <atomic>
#include <bit>

#include "harness/kernel/blocks.hpp"
#include "kernels/mpm/implicit.hpp"
#include "kernels/mpm/scatter.hpp"

namespace suite::mpm {

namespace {

struct Inputs {
    const double* shape;
    const std::uint32_t* conn;
    const std::int32_t* index;
    const std::uint32_t* block;
    const std::uint32_t* row_ptr;
    const double* du;
    const Particles* pt;
    const std::int32_t* nb;
    const double* evol;  // mixed integration's sums, or null
    double lambda, mu;
    bool large, tangent;
};

// Particle p's force entries f[3 i + a] and, with in.tangent, tangent entries k[(3 i + a) 12 + 3 j + b].
inline void particle_terms(const Inputs& in, std::size_t p, double* f, double* k) {
    const Particles& pt = *in.pt;
    const std::size_t e = pt.elem[p];
    const double* s = in.shape + 16 * e;
    double g[4][3];
    double F[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    for (int i = 0; i < 4; ++i) {
        for (int b = 0; b < 3; ++b) g[i][b] = s[4 * i + 1 + b];
        const double* u = in.du + 3 * static_cast<std::size_t>(in.index[in.conn[4 * e + i]]);
        for (int a = 0; a < 3; ++a)
            for (int b = 0; b < 3; ++b) F[a][b] += u[a] * g[i][b];
    }
    const double sg[3][3] = {{pt.stress[0][p], pt.stress[3][p], pt.stress[5][p]},
                             {pt.stress[3][p], pt.stress[1][p], pt.stress[4][p]},
                             {pt.stress[5][p], pt.stress[4][p], pt.stress[2][p]}};
    double E[3][3];
    for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) {
            double ftf = 0;
            for (int c = 0; c < 3; ++c) ftf += F[c][a] * F[c][b];
            E[a][b] = in.large ? 0.5 * (ftf - (a == b ? 1 : 0)) : 0.5 * (F[a][b] + F[b][a]) - (a == b ? 1 : 0);
        }
    const double tr = E[0][0] + E[1][1] + E[2][2];
    double S[3][3], P[3][3];
    for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) S[a][b] = sg[a][b] + 2 * in.mu * E[a][b] + (a == b ? in.lambda * tr : 0);
    for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b)
            P[a][b] = in.large ? F[a][0] * S[0][b] + F[a][1] * S[1][b] + F[a][2] * S[2][b] : S[a][b];
    double vol = pt.volume[p];
    if (in.evol) vol *= volume_scale(static_cast<std::uint32_t>(e), in.shape, in.nb, in.evol);
    for (int i = 0; i < 4; ++i)
        for (int a = 0; a < 3; ++a) f[3 * i + a] = vol * (P[a][0] * g[i][0] + P[a][1] * g[i][1] + P[a][2] * g[i][2]);
    if (!in.tangent) return;
    // G_i = F ∇N_i; FFᵀ; K_(ia)(jb) = V (δ_ab ∇N_i·S∇N_j + λ G_ia G_jb + μ (∇N_i·∇N_j)(FFᵀ)_ab + μ G_ja G_ib),
    // which is the small-strain stiffness at F = I, S = 0 (the geometric term left out there).
    double G[4][3], FF[3][3];
    for (int i = 0; i < 4; ++i)
        for (int a = 0; a < 3; ++a) G[i][a] = F[a][0] * g[i][0] + F[a][1] * g[i][1] + F[a][2] * g[i][2];
    for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) FF[a][b] = F[a][0] * F[b][0] + F[a][1] * F[b][1] + F[a][2] * F[b][2];
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) {
            double gg = 0, gsg = 0;
            for (int a = 0; a < 3; ++a) {
                gg += g[i][a] * g[j][a];
                if (in.large)
                    for (int b = 0; b < 3; ++b) gsg += g[i][a] * S[a][b] * g[j][b];
            }
            for (int a = 0; a < 3; ++a)
                for (int b = 0; b < 3; ++b) {
                    const double kab = in.large ? (a == b ? gsg : 0) + in.lambda * G[i][a] * G[j][b] +
                                                      in.mu * gg * FF[a][b] + in.mu * G[j][a] * G[i][b]
                                                : in.lambda * g[i][a] * g[j][b] + in.mu * (a == b ? gg : 0) +
                                                      in.mu * g[j][a] * g[i][b];
                    k[(3 * i + a) * 12 + 3 * j + b] = vol * kab;
                }
        }
}

// Adds particle p's terms into the force and the tangent; Atomic: every addition (or, for
// the partition, those into rows of a shared node: `shared` non-null) atomic.
template <bool Atomic>
inline void add_particle(const Inputs& in, std::size_t p, double* fint, double* val, const std::uint64_t* shared) {
    double f[12], k[144];
    particle_terms(in, p, f, k);
    const std::size_t e = in.pt->elem[p];
    for (int i = 0; i < 4; ++i) {
        const std::uint32_t node = in.conn[4 * e + i];
        const bool sync = Atomic && (shared == nullptr || std::popcount(shared[node]) > 1);
        const std::size_t row0 = 3 * static_cast<std::size_t>(in.index[node]);
        for (int a = 0; a < 3; ++a) {
            double* fr = fint + row0 + a;
            if (sync)
                std::atomic_ref<double>(*fr).fetch_add(f[3 * i + a], std::memory_order_relaxed);
            else
                *fr += f[3 * i + a];
            if (!in.tangent) continue;
            for (int j = 0; j < 4; ++j) {
                double* v = val + in.row_ptr[row0 + a] + in.block[16 * e + 4 * i + j];
                const double* kk = k + (3 * i + a) * 12 + 3 * j;
                for (int b = 0; b < 3; ++b) {
                    if (sync)
                        std::atomic_ref<double>(v[b]).fetch_add(kk[b], std::memory_order_relaxed);
                    else
                        v[b] += kk[b];
                }
            }
        }
    }
}

}  // namespace

void implicit_assemble(State& st, bool tangent) {
    ActiveSystem& sys = st.system;
    const Material& mat = st.settings.material;
    Inputs in;
    in.shape = st.grid.shape.data();
    in.conn = st.grid.mesh.conn.data();
    in.index = sys.index.data();
    in.block = sys.block.data();
    in.row_ptr = sys.row_ptr.data();
    in.du = sys.du.data();
    in.pt = &st.particles;
    in.nb = st.grid.neighbour.data();
    in.evol = st.settings.integration == Integration::mixed ? st.element_volume.data() : nullptr;
    in.lambda = mat.young * mat.poisson / ((1 + mat.poisson) * (1 - 2 * mat.poisson));
    in.mu = mat.young / (2 * (1 + mat.poisson));
    in.large = st.settings.implicit.large_strain;
    in.tangent = tangent;
    double* const fint = sys.fint.data();
    double* const val = sys.val.data();
    const std::int64_t rows = static_cast<std::int64_t>(sys.rows()), nnz = static_cast<std::int64_t>(sys.val.size());
    const std::int64_t np = static_cast<std::int64_t>(st.particles.size());
    const ScatterPlan& plan = st.plan;
    const Bins& bins = st.bins;
#pragma omp parallel
    {
        const Block rb = my_block(rows);
        for (std::int64_t i = rb.lo; i < rb.hi; ++i) fint[i] = 0;
        if (tangent) {
            const Block vb = my_block(nnz);
            for (std::int64_t k = vb.lo; k < vb.hi; ++k) val[k] = 0;
        }
#pragma omp barrier
        switch (plan.strategy) {
            case Strategy::serial:
#pragma omp single
                for (std::int64_t p = 0; p < np; ++p)
                    add_particle<false>(in, static_cast<std::size_t>(p), fint, val, nullptr);
                break;
            case Strategy::atomic: {
                const Block b = my_block(np);
                for (std::int64_t p = b.lo; p < b.hi; ++p)
                    add_particle<true>(in, static_cast<std::size_t>(p), fint, val, nullptr);
                break;
            }
            case Strategy::colour:
                for (int c = 0; c < plan.colours(); ++c) {
                    const std::int64_t lo = plan.colour_start[c], n = plan.colour_start[c + 1] - lo;
                    const Block b = my_block(n);
                    for (std::int64_t j = lo + b.lo; j < lo + b.hi; ++j) {
                        const std::uint32_t e = plan.colour_elems[j];
                        for (std::uint32_t q = bins.start[e]; q < bins.start[e + 1]; ++q)
                            add_particle<false>(in, bins.order[q], fint, val, nullptr);
                    }
#pragma omp barrier
                }
                break;
            case Strategy::partition: {
                // The runs and the nodes' masks of the projection's scatter (implicit_project), whose
                // particles and elements these are.
                const int t = omp_get_thread_num();
                for (std::uint32_t e = plan.run_start[t]; e < plan.run_start[t + 1]; ++e)
                    for (std::uint32_t q = bins.start[e]; q < bins.start[e + 1]; ++q)
                        add_particle<true>(in, bins.order[q], fint, val, plan.touched.data());
                break;
            }
        }
    }
}

}  // namespace suite::mpm
