// The implicit step of implicit.hpp: the projection and the active system, Newton's loop, the
// particle update. The assembly is implicit_assembly.cpp, the linear solves implicit_solve.cpp.
#include "kernels/mpm/implicit.hpp"

#include <algorithm>
#include <cmath>

#include "harness/common/units.hpp"
#include "kernels/fem/sparse_libs.hpp"
#include "kernels/mpm/choices.hpp"
#include "kernels/mpm/scatter.hpp"

namespace suite::mpm {

Integrator parse_integrator(const std::string& name) { return integrators().at(name).what; }

const char* integrator_name(Integrator i) { return name_of(integrators(), i).c_str(); }

LinearSolver parse_linear_solver(const std::string& name) { return linear_solvers().at(name).what; }

const char* linear_solver_name(LinearSolver s) { return name_of(linear_solvers(), s).c_str(); }

void check_implicit(const Settings& s) {
    if (s.integrator == Integrator::explicit_step) return;
    if (s.material.model != Material::Model::elastic)
        throw UsageError(std::string("--integrator=") + integrator_name(s.integrator) +
                         ": the implicit integrators have the elastic material only (--case=" + elastic_cases() +
                         "); "
                         "the fluid runs --integrator=explicit");
    if (s.damping != 0)
        throw UsageError(
            "--damping applies to --integrator=explicit; --integrator=static gives the quasi-static answer without it");
    const ImplicitSettings& im = s.implicit;
    if (!(im.gamma >= 0.5 && 2 * im.beta >= im.gamma && 2 * im.beta <= 1))
        throw UsageError("--newmark=" + format_number(im.beta) + "," + format_number(im.gamma) +
                         ": Newmark's β, γ must satisfy 1/2 <= γ <= 2β <= 1 (unconditionally stable; 0.25,0.5 is "
                         "average acceleration)");
    // Settings the command line does not set (a caller's), each named as the field it is.
    if (!(im.residual_tol > 0 && im.residual_tol < 1))
        throw UsageError("ImplicitSettings::residual_tol=" + format_number(im.residual_tol) +
                         ": Newton's relative residual tolerance must lie in (0, 1)");
    if (!(im.increment_tol > 0 && im.increment_tol < 1))
        throw UsageError("ImplicitSettings::increment_tol=" + format_number(im.increment_tol) +
                         ": Newton's relative increment tolerance must lie in (0, 1)");
    if (im.newton_max < 1 || im.newton_max > 1000)
        throw UsageError("--newton-max=" + std::to_string(im.newton_max) +
                         ": Newton's iteration limit is a whole number from 1 to 1000");
    if (im.cg_max < 1)
        throw UsageError("ImplicitSettings::cg_max=" + std::to_string(im.cg_max) +
                         ": CG's iteration limit must be >= 1");
    if (!(im.cg_tol > 0 && im.cg_tol < 1))
        throw UsageError("ImplicitSettings::cg_tol=" + format_number(im.cg_tol) +
                         ": CG's relative tolerance must lie in (0, 1)");
    if (im.solver == LinearSolver::cholmod && !fem::sparse_libs_missing().empty())
        throw UsageError("--solver=cholmod: this suite was built without " + fem::sparse_libs_missing() +
                         "; give --solver=cg");
}

namespace {

bool is_static(const State& st) { return st.settings.integrator == Integrator::quasi_static; }

// The active elements (holding particles), ascending; the system's pattern rebuilt when they
// changed since the last step.
void build_system(State& st) {
    ActiveSystem& sys = st.system;
    const Particles& pt = st.particles;
    const std::size_t ne = st.grid.elements(), nv = st.grid.nodes();
    std::vector<std::uint8_t> holds(ne, 0);
    for (std::size_t p = 0; p < pt.size(); ++p) holds[pt.elem[p]] = 1;
    std::vector<std::uint32_t> elements;
    for (std::size_t e = 0; e < ne; ++e)
        if (holds[e]) elements.push_back(static_cast<std::uint32_t>(e));
    if (elements == sys.elements && sys.index.size() == nv) return;
    sys.elements = std::move(elements);
    const std::uint32_t* const conn = st.grid.mesh.conn.data();
    sys.index.assign(nv, -1);
    for (std::uint32_t e : sys.elements)
        for (int i = 0; i < 4; ++i) sys.index[conn[4 * static_cast<std::size_t>(e) + i]] = 0;
    sys.node.clear();
    for (std::size_t v = 0; v < nv; ++v)
        if (sys.index[v] == 0) {
            sys.index[v] = static_cast<std::int32_t>(sys.node.size());
            sys.node.push_back(static_cast<std::uint32_t>(v));
        }
    // Node pairs sharing an active element: (row << 32 | column), sorted and unique.
    std::vector<std::uint64_t> pairs;
    pairs.reserve(16 * sys.elements.size());
    for (std::uint32_t e : sys.elements)
        for (int i = 0; i < 4; ++i)
            for (int j = 0; j < 4; ++j)
                pairs.push_back(static_cast<std::uint64_t>(sys.index[conn[4 * static_cast<std::size_t>(e) + i]]) << 32 |
                                static_cast<std::uint32_t>(sys.index[conn[4 * static_cast<std::size_t>(e) + j]]));
    std::sort(pairs.begin(), pairs.end());
    pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
    const std::size_t n = sys.node.size();
    std::vector<std::uint64_t> first(n + 1, 0);  // node row r's pairs: [first[r], first[r + 1])
    for (std::uint64_t q : pairs) ++first[(q >> 32) + 1];
    for (std::size_t r = 0; r < n; ++r) first[r + 1] += first[r];
    if (9 * pairs.size() >= (1ULL << 32))
        throw UsageError("MPM implicit: the active system has 2^32 nonzeros or more; give a coarser grid");
    sys.row_ptr.assign(3 * n + 1, 0);
    sys.col.resize(9 * pairs.size());
    std::uint32_t at = 0;
    for (std::size_t r = 0; r < n; ++r)
        for (int a = 0; a < 3; ++a) {
            sys.row_ptr[3 * r + a] = at;
            for (std::uint64_t q = first[r]; q < first[r + 1]; ++q)
                for (int b = 0; b < 3; ++b)
                    sys.col[at++] =
                        3 * static_cast<std::uint32_t>(pairs[q] & 0xffffffffu) + static_cast<std::uint32_t>(b);
        }
    sys.row_ptr[3 * n] = at;
    sys.val.assign(at, 0);
    sys.block.assign(16 * ne, 0);
    for (std::uint32_t e : sys.elements)
        for (int i = 0; i < 4; ++i) {
            const std::uint64_t r = static_cast<std::uint64_t>(sys.index[conn[4 * static_cast<std::size_t>(e) + i]]);
            for (int j = 0; j < 4; ++j) {
                const std::uint64_t key =
                    r << 32 | static_cast<std::uint32_t>(sys.index[conn[4 * static_cast<std::size_t>(e) + j]]);
                const auto it = std::lower_bound(pairs.begin() + static_cast<std::ptrdiff_t>(first[r]),
                                                 pairs.begin() + static_cast<std::ptrdiff_t>(first[r + 1]), key);
                sys.block[16 * static_cast<std::size_t>(e) + 4 * i + j] =
                    3 * static_cast<std::uint32_t>(it - (pairs.begin() + static_cast<std::ptrdiff_t>(first[r])));
            }
        }
    ++sys.patterns;
}

double norm(const std::vector<double>& v) {
    double s = 0;
    const std::int64_t n = static_cast<std::int64_t>(v.size());
#pragma omp parallel for schedule(static) reduction(+ : s)
    for (std::int64_t i = 0; i < n; ++i) s += v[i] * v[i];
    return std::sqrt(s);
}

}  // namespace

void implicit_project(State& st) {
    Particles& pt = st.particles;
    if (pt.accel[0].size() != pt.size()) pt.add_accelerations(nullptr);
    NodeState* const nodes = st.nodes.data();
    const std::int64_t nn = st.node_hi;
#pragma omp parallel for schedule(static)
    for (std::int64_t n = 0; n < nn; ++n) nodes[n] = NodeState{};
    const bool quiet = is_static(st);
    // c per corner: m, m v (into p), m a (into f).
    scatter<0, 7>(st, [&](std::size_t p, double* c) {
        const double m = pt.mass[p];
        const double v[3] = {pt.vx[p], pt.vy[p], pt.vz[p]};
        const double a[3] = {pt.accel[0][p], pt.accel[1][p], pt.accel[2][p]};
        for (int i = 0; i < 4; ++i) {
            const double wm = pt.w[4 * p + i] * m;
            double* ci = c + 7 * i;
            ci[0] = wm;
            for (int k = 0; k < 3; ++k) {
                ci[1 + k] = quiet ? 0 : wm * v[k];
                ci[4 + k] = quiet ? 0 : wm * a[k];
            }
        }
    });
    if (st.settings.integration == Integration::mixed) sum_element_volumes(st);
    build_system(st);
    ActiveSystem& sys = st.system;
    const std::size_t n = sys.node.size(), rows = 3 * n;
    for (auto* v : {&sys.v, &sys.a, &sys.fext, &sys.fint, &sys.du, &sys.r, &sys.delta}) v->assign(rows, 0);
    sys.mass.assign(n, 0);
    sys.fixed.assign(rows, 0);
    const double* g = st.settings.gravity;
    for (std::size_t k = 0; k < n; ++k) {
        const std::uint32_t node = sys.node[k];
        const NodeState& s = nodes[node];
        const double m = s.m;
        sys.mass[k] = m;
        for (int a = 0; a < 3; ++a) {
            const std::size_t row = 3 * k + static_cast<std::size_t>(a);
            sys.fixed[row] = (st.grid.wall[node] >> a) & 1;
            sys.fext[row] = m * g[a];
            if (sys.fixed[row] || !(m > 0)) continue;
            sys.v[row] = s.p[a] / m;
            sys.a[row] = s.f[a] / m;
        }
    }
    st.implicit.active_rows = rows;
    st.implicit.nonzeros = sys.row_ptr.empty() ? 0 : sys.row_ptr.back();
}

double implicit_residual(State& st) {
    ActiveSystem& sys = st.system;
    const bool quiet = is_static(st);
    const double dt = st.dt, beta = st.settings.implicit.beta;
    const std::int64_t rows = static_cast<std::int64_t>(sys.rows());
    double s = 0;
#pragma omp parallel for schedule(static) reduction(+ : s)
    for (std::int64_t i = 0; i < rows; ++i) {
        double r = 0;
        if (!sys.fixed[i]) {
            r = sys.fext[i] - sys.fint[i];
            if (!quiet) {
                const double a_new = (sys.du[i] - dt * sys.v[i] - dt * dt * (0.5 - beta) * sys.a[i]) / (beta * dt * dt);
                r -= sys.mass[i / 3] * a_new;
            }
        }
        sys.r[i] = r;
        s += r * r;
    }
    return std::sqrt(s);
}

void implicit_finish_tangent(State& st) {
    ActiveSystem& sys = st.system;
    const double inertia = is_static(st) ? 0 : 1 / (st.settings.implicit.beta * st.dt * st.dt);
    const std::int64_t rows = static_cast<std::int64_t>(sys.rows());
#pragma omp parallel for schedule(static)
    for (std::int64_t i = 0; i < rows; ++i)
        for (std::uint32_t k = sys.row_ptr[i]; k < sys.row_ptr[i + 1]; ++k) {
            const std::uint32_t j = sys.col[k];
            if (sys.fixed[i] || sys.fixed[j])
                sys.val[k] = i == j ? 1 : 0;
            else if (i == j)
                sys.val[k] += sys.mass[i / 3] * inertia;
        }
}

void implicit_update(State& st) {
    ActiveSystem& sys = st.system;
    Particles& pt = st.particles;
    const Material& mat = st.settings.material;
    const double lambda = mat.young * mat.poisson / ((1 + mat.poisson) * (1 - 2 * mat.poisson));
    const double mu = mat.young / (2 * (1 + mat.poisson));
    const bool quiet = is_static(st), large = st.settings.implicit.large_strain;
    const double dt = st.dt, beta = st.settings.implicit.beta, gamma = st.settings.implicit.gamma;
    const std::uint32_t* const conn = st.grid.mesh.conn.data();
    const double* const shape = st.grid.shape.data();
    const double lo[3] = {st.grid.lo[0], st.grid.lo[1], st.grid.lo[2]},
                 hi[3] = {st.grid.hi[0], st.grid.hi[1], st.grid.hi[2]};
    double* const pos[3] = {pt.x.data(), pt.y.data(), pt.z.data()};
    double* const vel[3] = {pt.vx.data(), pt.vy.data(), pt.vz.data()};
    double* const acc[3] = {pt.accel[0].data(), pt.accel[1].data(), pt.accel[2].data()};
    const std::int64_t np = static_cast<std::int64_t>(pt.size());
    std::uint64_t clamped = 0;
#pragma omp parallel for schedule(static) reduction(+ : clamped)
    for (std::int64_t p = 0; p < np; ++p) {
        const std::size_t e = pt.elem[p];
        const double* s = shape + 16 * e;
        const double* w = &pt.w[4 * p];
        double f[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
        double dx[3] = {0, 0, 0}, dv[3] = {0, 0, 0}, an[3] = {0, 0, 0};
        for (int i = 0; i < 4; ++i) {
            const std::size_t row = 3 * static_cast<std::size_t>(sys.index[conn[4 * e + i]]);
            for (int a = 0; a < 3; ++a) {
                const double du = sys.du[row + a];
                for (int b = 0; b < 3; ++b) f[a][b] += du * s[4 * i + 1 + b];
                dx[a] += w[i] * du;
                if (quiet) continue;
                const double v = sys.v[row + a], acc0 = sys.a[row + a];
                const double a_new =
                    sys.fixed[row + a] ? 0 : (du - dt * v - dt * dt * (0.5 - beta) * acc0) / (beta * dt * dt);
                dv[a] += w[i] * dt * ((1 - gamma) * acc0 + gamma * a_new);
                an[a] += w[i] * a_new;
            }
        }
        const double sg[3][3] = {{pt.stress[0][p], pt.stress[3][p], pt.stress[5][p]},
                                 {pt.stress[3][p], pt.stress[1][p], pt.stress[4][p]},
                                 {pt.stress[5][p], pt.stress[4][p], pt.stress[2][p]}};
        double e_[3][3], out[3][3];
        for (int a = 0; a < 3; ++a)
            for (int b = 0; b < 3; ++b) {
                double ftf = 0;
                for (int k = 0; k < 3; ++k) ftf += f[k][a] * f[k][b];
                e_[a][b] = large ? 0.5 * (ftf - (a == b ? 1 : 0)) : 0.5 * (f[a][b] + f[b][a]) - (a == b ? 1 : 0);
            }
        const double tr = e_[0][0] + e_[1][1] + e_[2][2];
        double S[3][3];
        for (int a = 0; a < 3; ++a)
            for (int b = 0; b < 3; ++b) S[a][b] = sg[a][b] + 2 * mu * e_[a][b] + (a == b ? lambda * tr : 0);
        double j = 1 + tr;
        if (large) {
            j = f[0][0] * (f[1][1] * f[2][2] - f[1][2] * f[2][1]) - f[0][1] * (f[1][0] * f[2][2] - f[1][2] * f[2][0]) +
                f[0][2] * (f[1][0] * f[2][1] - f[1][1] * f[2][0]);
            double fs[3][3];
            for (int a = 0; a < 3; ++a)
                for (int b = 0; b < 3; ++b) fs[a][b] = f[a][0] * S[0][b] + f[a][1] * S[1][b] + f[a][2] * S[2][b];
            for (int a = 0; a < 3; ++a)
                for (int b = 0; b < 3; ++b)
                    out[a][b] = (fs[a][0] * f[b][0] + fs[a][1] * f[b][1] + fs[a][2] * f[b][2]) / j;
        } else {
            for (int a = 0; a < 3; ++a)
                for (int b = 0; b < 3; ++b) out[a][b] = S[a][b];
        }
        pt.volume[p] *= j;
        pt.stress[0][p] = out[0][0];
        pt.stress[1][p] = out[1][1];
        pt.stress[2][p] = out[2][2];
        pt.stress[3][p] = 0.5 * (out[0][1] + out[1][0]);
        pt.stress[4][p] = 0.5 * (out[1][2] + out[2][1]);
        pt.stress[5][p] = 0.5 * (out[2][0] + out[0][2]);
        bool outside = false;
        for (int a = 0; a < 3; ++a) {
            vel[a][p] = quiet ? 0 : vel[a][p] + dv[a];
            acc[a][p] = quiet ? 0 : an[a];
            double x = pos[a][p] + dx[a];
            if (x < lo[a] || x > hi[a]) {
                x = std::clamp(x, lo[a], hi[a]);
                outside = true;
            }
            pos[a][p] = x;
        }
        clamped += outside ? 1 : 0;
    }
    st.clamped += clamped;
    locate(st);
}

void implicit_step(State& st) {
    ImplicitStats& stats = st.implicit;
    const ImplicitSettings& im = st.settings.implicit;
    ActiveSystem& sys = st.system;
    // The counts are the state's only when the step succeeds: a failed one leaves them (and the
    // particles) as they were, its residuals and why kept for the message.
    const ImplicitStats before = stats;
    std::vector<double> residuals;
    const auto fail = [&](const std::string& why) {
        stats = before;
        stats.failure = why;
        stats.last_residuals = residuals;
        ++stats.failed_steps;
    };
    implicit_project(st);
    if (is_static(st)) {
        // Without inertia, a material no wall holds in some direction moves freely in it: K is singular.
        for (int a = 0; a < 3; ++a) {
            bool held = false;
            for (std::size_t i = static_cast<std::size_t>(a); i < sys.rows() && !held; i += 3) held = sys.fixed[i] != 0;
            if (!held)
                return fail(std::string("the static system is singular: no wall holds the material in ") + "xyz"[a] +
                            " (it would move freely; run --integrator=implicit, whose inertia holds it)");
        }
    }
    // The load the free rows carry (a wall takes the fixed rows' share).
    double load = 0;
    for (std::size_t i = 0; i < sys.rows(); ++i)
        if (!sys.fixed[i]) load += sys.fext[i] * sys.fext[i];
    load = std::sqrt(load);
    std::uint64_t newton = 0, solver_iterations = 0;
    double r0 = 0, reference = 0, du_norm = 0, delta_norm = 0, previous = 0;
    for (int k = 0;; ++k) {
        implicit_assemble(st, true);
        double rn = implicit_residual(st);
        // Backtracking: a correction that made the residual larger is halved, up to 8 times (a
        // step whose strain the first tangent misjudged; rare, counted in backtracks).
        for (double alpha = 1; k > 0 && !(rn <= previous) && alpha > 1.0 / 256;) {
            alpha /= 2;
            for (std::size_t i = 0; i < sys.rows(); ++i) sys.du[i] -= alpha * sys.delta[i];
            ++stats.backtracks;
            implicit_assemble(st, true);
            rn = implicit_residual(st);
        }
        previous = rn;
        if (k == 0) {
            r0 = rn;
            reference = std::max(r0, load);
        }
        residuals.push_back(reference > 0 ? rn / reference : 0);
        if (rn <= im.residual_tol * reference || (k > 0 && delta_norm <= im.increment_tol * du_norm)) break;
        if (k == im.newton_max || !std::isfinite(rn))
            return fail("Newton did not converge in " + std::to_string(im.newton_max) +
                        " iterations (||r|| / max(||r0||, ||m g||) = " + format_number(rn / reference) +
                        ", tolerance " + format_number(im.residual_tol) + "); give a smaller --dt");
        implicit_finish_tangent(st);
        std::string why;
        const long its = implicit_solve(st, why);
        if (its < 0) return fail(why);
        solver_iterations += static_cast<std::uint64_t>(its);
        ++newton;
        for (std::size_t i = 0; i < sys.rows(); ++i) sys.du[i] += sys.delta[i];
        delta_norm = norm(sys.delta);
        du_norm = norm(sys.du);
    }
    const int iterations = static_cast<int>(residuals.size()) - 1;
    stats.failure.clear();
    stats.newton += newton;
    stats.solver_iterations += solver_iterations;
    stats.last_newton = iterations;
    stats.max_newton = std::max(stats.max_newton, iterations);
    stats.worst_residual = std::max(stats.worst_residual, residuals.back());
    stats.last_residuals = std::move(residuals);
    implicit_update(st);
}

}  // namespace suite::mpm
