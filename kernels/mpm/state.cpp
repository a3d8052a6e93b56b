// A simulation's state at time 0 (the checks of its settings, the particles seeded in the
// material's region), the strategies' names, and the sums the checks read.
#include <sys/mman.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <iterator>
#include <stdexcept>
#include <string>

#include "harness/common/units.hpp"
#include "harness/kernel/arena.hpp"
#include "harness/kernel/blocks.hpp"
#include "kernels/mpm/choices.hpp"
#include "kernels/mpm/implicit.hpp"
#include "kernels/mpm/mpm.hpp"

namespace suite::mpm {

void Particles::resize(std::size_t n) {
    for (auto* v : {&x, &y, &z, &vx, &vy, &vz, &mass, &volume}) v->resize(n);
    for (auto& s : stress) s.resize(n);
    w.resize(4 * n);
    elem.resize(n);
    id.resize(n);
}

void Particles::add_accelerations(Arena* arena) {
    const std::size_t n = size();
    constexpr const char* names[] = {"ax", "ay", "az"};
    for (int k = 0; k < 3; ++k) {
        if (arena)
            accel[k] = Array<double>::placed(arena->allocate<double>(names[k], n), n);
        else
            accel[k].resize(n);
    }
    double* const d[] = {accel[0].data(), accel[1].data(), accel[2].data()};
    const std::int64_t count = static_cast<std::int64_t>(n);
#pragma omp parallel
    {
        const Block b = my_block(count);  // the particle loops' split, as place() touches
        for (double* v : d) std::fill(v + b.lo, v + b.hi, 0.0);
    }
}

void Particles::place(std::size_t n, Arena& arena) {
    Array<double>* const doubles[] = {&x,      &y,         &z,         &vx,        &vy,        &vz,        &mass,
                                      &volume, &stress[0], &stress[1], &stress[2], &stress[3], &stress[4], &stress[5]};
    constexpr std::size_t nd = std::size(doubles);
    static_assert(std::size(particle_array_names) == nd + 3, "a name for every particle array");
    for (std::size_t k = 0; k < nd; ++k)
        *doubles[k] = Array<double>::placed(arena.allocate<double>(particle_array_names[k], n), n);
    w = Array<double>::placed(arena.allocate<double>(particle_array_names[nd], 4 * n), 4 * n);
    elem = Array<std::uint32_t>::placed(arena.allocate<std::uint32_t>(particle_array_names[nd + 1], n), n);
    id = Array<std::uint32_t>::placed(arena.allocate<std::uint32_t>(particle_array_names[nd + 2], n), n);
    scratch.buf = Array<double>::placed(arena.allocate<double>("reorder-scratch", 4 * n), 4 * n);
    double* d[nd];
    for (std::size_t k = 0; k < nd; ++k) d[k] = doubles[k]->data();
    double* const wp = w.data();
    double* const sp = scratch.buf.data();
    std::uint32_t* const ep = elem.data();
    std::uint32_t* const ip = id.data();
    const std::int64_t count = static_cast<std::int64_t>(n);
    // The first touch: the split of every `parallel for schedule(static)` over particles.
#pragma omp parallel
    {
        const Block b = my_block(count);
        for (std::size_t k = 0; k < nd; ++k) std::fill(d[k] + b.lo, d[k] + b.hi, 0.0);
        std::fill(wp + 4 * b.lo, wp + 4 * b.hi, 0.0);
        std::fill(sp + 4 * b.lo, sp + 4 * b.hi, 0.0);
        std::fill(ep + b.lo, ep + b.hi, 0u);
        std::fill(ip + b.lo, ip + b.hi, 0u);
    }
}

void touch_nodes(State& st, bool fresh) {
    Array<NodeState>& nodes = st.nodes;
    const std::int64_t nn = static_cast<std::int64_t>(nodes.size());
    const std::int64_t hi = std::min<std::int64_t>(st.node_hi, nn);
    if (fresh && nodes.placed() && nn > 0) {
        // The arena gave the nodes whole pages of their own (arena.hpp), page-aligned.
        const auto page = static_cast<std::size_t>(sysconf(_SC_PAGESIZE));
        const std::size_t bytes = (static_cast<std::size_t>(nn) * sizeof(NodeState) + page - 1) / page * page;
        if (madvise(nodes.data(), bytes, MADV_DONTNEED) != 0)
            throw std::runtime_error(
                std::string("MPM: cannot drop the nodes' pages for a fresh first touch: madvise: ") +
                std::strerror(errno));
    }
    NodeState* const d = nodes.data();
#pragma omp parallel
    {
        const Block a = my_block(hi), b = my_block(nn - hi);
        for (std::int64_t n = a.lo; n < a.hi; ++n) d[n] = NodeState{};
        for (std::int64_t n = hi + b.lo; n < hi + b.hi; ++n) d[n] = NodeState{};
    }
}

void place_grid_arrays(State& st, Arena& arena) {
    const std::size_t nn = st.grid.nodes(), ne = st.grid.elements();
    st.nodes = Array<NodeState>::placed(arena.allocate<NodeState>("nodes", nn), nn);
    touch_nodes(st, false);  // untouched pages: this is their first touch
    if (st.settings.integration != Integration::mixed) return;
    double* const ev = arena.allocate<double>("element-volume", ne);
    const std::int64_t count = static_cast<std::int64_t>(ne);
    // The split of sum_element_volumes' zeroing loop (step.cpp).
#pragma omp parallel for schedule(static)
    for (std::int64_t e = 0; e < count; ++e) ev[e] = 0;
    st.element_volume = Array<double>::placed(ev, ne);
}

Strategy parse_strategy(const std::string& name) { return strategies().at(name).what; }

const char* strategy_name(Strategy s) { return name_of(strategies(), s).c_str(); }

ScatterPlan plan_scatter(const Grid& g, Strategy s, int threads) {
    ScatterPlan plan;
    plan.strategy = s;
    plan.threads = s == Strategy::serial ? 1 : threads;
    if (s == Strategy::colour) plan_colours(g, plan);
    if (s == Strategy::partition) plan_partition(g, plan);
    return plan;
}

namespace {

// Barycentric coordinates of the seeding points of one element: the centroid for 1, the
// 4-point Gauss rule for 4, otherwise the first n points of the R3 low-discrepancy sequence
// folded from the unit cube into the tetrahedron (Rocchini and Cignoni's folds).
std::vector<std::array<double, 4>> seed_points(int n) {
    std::vector<std::array<double, 4>> out;
    if (n == 1) return {{0.25, 0.25, 0.25, 0.25}};
    if (n == 4) {
        const double a = 0.5854101966249685, b = 0.1381966011250105;
        return {{a, b, b, b}, {b, a, b, b}, {b, b, a, b}, {b, b, b, a}};
    }
    const double alpha[3] = {0.8191725133961645, 0.6710436067037893, 0.5497004779019703};
    for (int k = 0; k < n; ++k) {
        double s = std::fmod(0.5 + alpha[0] * (k + 1), 1.0), t = std::fmod(0.5 + alpha[1] * (k + 1), 1.0),
               u = std::fmod(0.5 + alpha[2] * (k + 1), 1.0);
        if (s + t > 1) {
            s = 1 - s;
            t = 1 - t;
        }
        if (t + u > 1) {
            const double tmp = u;
            u = 1 - s - t;
            t = 1 - tmp;
        } else if (s + t + u > 1) {
            const double tmp = u;
            u = s + t + u - 1;
            s = 1 - t - tmp;
        }
        out.push_back({1 - s - t - u, s, t, u});
    }
    return out;
}

std::string triple(const double* v) {
    return format_number(v[0]) + "," + format_number(v[1]) + "," + format_number(v[2]);
}

void check_settings(const Grid& g, const Settings& s, bool force) {
    const Material& m = s.material;
    if (s.per_element < 1)
        throw UsageError("--ppe=" + std::to_string(s.per_element) +
                         ": particles per element must be a whole number >= 1");
    if (m.model == Material::Model::fluid) {
        if (!(m.sound_speed > 0) || !std::isfinite(m.sound_speed))
            throw UsageError("--sound-speed=" + format_number(m.sound_speed) +
                             ": the fluid's sound speed must be > 0 (m/s)");
        if (!(m.viscosity >= 0) || !std::isfinite(m.viscosity))
            throw UsageError("--viscosity=" + format_number(m.viscosity) +
                             ": the fluid's dynamic viscosity must be >= 0 (Pa s)");
    } else {
        if (!(m.young > 0) || !std::isfinite(m.young))
            throw UsageError("--young=" + format_number(m.young) + ": Young's modulus E must be > 0 (Pa)");
        if (!(m.poisson > -1 && m.poisson < 0.5))
            throw UsageError("--poisson=" + format_number(m.poisson) +
                             ": Poisson's ratio must lie in (-1, 0.5); 0.5 is incompressible, which an explicit "
                             "elastic step cannot take");
    }
    if (!(m.density > 0) || !std::isfinite(m.density))
        throw UsageError("--density=" + format_number(m.density) + ": the density must be > 0 (kg/m³)");
    const Region& r = s.region;
    for (int a = 0; a < 3; ++a)
        if (!(r.lo[a] < r.hi[a]) || r.lo[a] < g.lo[a] - 1e-12 || r.hi[a] > g.hi[a] + 1e-12)
            throw UsageError("the material's region [" + triple(r.lo) + "] to [" + triple(r.hi) +
                             "] is not a box inside the grid's box [" + triple(g.lo) + "] to [" + triple(g.hi) + "]");
    if (!(s.damping >= 0) || !(s.damping * critical_step(g, m) <= 1))
        throw UsageError("--damping=" + format_number(s.damping) +
                         ": the damping c (1/s) must be >= 0 and at most 1 / the stable step (" +
                         format_number(1 / critical_step(g, m)) +
                         " here), beyond which one step would reverse a node's momentum");
    if (!(s.courant > 0) || (s.courant > 1 && !force))
        throw UsageError(
            "--courant=" + format_number(s.courant) +
            ": the Courant number must lie in (0, 1] (above 1 the step is unstable; --force runs it anyway)");
    const double critical = critical_step(g, m);
    if (!(s.dt >= 0) || !std::isfinite(s.dt))
        throw UsageError("--dt=" + format_number(s.dt) +
                         ": the time step must be a finite number of seconds > 0 (or 0: from the Courant number)");
    if (s.dt > critical && !force && s.integrator == Integrator::explicit_step)
        throw UsageError(
            "--dt=" + format_number(s.dt) + ": above the stable time step " + format_number(critical) +
            " s (smallest element altitude / elastic wave speed); give a smaller one, or --force to run it anyway");
}

}  // namespace

State make_state(Grid grid, const Settings& s, Strategy strategy, int threads, bool force, Arena* arena) {
    check_settings(grid, s, force);
    check_implicit(s);
    State st;
    st.settings = s;
    const double stable = critical_step(grid, s.material);
    st.dt = s.dt > 0                                    ? s.dt
            : s.integrator == Integrator::explicit_step ? s.courant * stable
                                                        : implicit_default_multiple * stable;
    const mesh::Mesh& m = grid.mesh;
    const std::size_t ne = grid.elements();
    std::vector<std::uint32_t> chosen;
    for (std::size_t e = 0; e < ne; ++e) {
        const std::uint32_t* c = &m.conn[4 * e];
        const double centre[3] = {(m.x[c[0]] + m.x[c[1]] + m.x[c[2]] + m.x[c[3]]) / 4,
                                  (m.y[c[0]] + m.y[c[1]] + m.y[c[2]] + m.y[c[3]]) / 4,
                                  (m.z[c[0]] + m.z[c[1]] + m.z[c[2]] + m.z[c[3]]) / 4};
        bool in = true;
        for (int a = 0; a < 3; ++a) in = in && centre[a] >= s.region.lo[a] && centre[a] <= s.region.hi[a];
        if (in) chosen.push_back(static_cast<std::uint32_t>(e));
    }
    if (chosen.empty())
        throw UsageError(
            "the material's region holds no element's centroid on this grid; make it larger or the grid finer");
    const auto points = seed_points(s.per_element);
    const std::size_t per = points.size();
    Particles& pt = st.particles;
    if (arena)
        pt.place(chosen.size() * per, *arena);
    else
        pt.resize(chosen.size() * per);
    if (s.integrator != Integrator::explicit_step) pt.add_accelerations(arena);
#pragma omp parallel for schedule(static)
    for (std::size_t k = 0; k < chosen.size(); ++k) {
        const std::size_t e = chosen[k];
        const std::uint32_t* c = &m.conn[4 * e];
        const double volume = std::fabs(mesh::signed_measure(m.view(), e)) / 6 / static_cast<double>(per);
        for (std::size_t j = 0; j < per; ++j) {
            const std::size_t p = k * per + j;
            const auto& l = points[j];
            pt.x[p] = pt.y[p] = pt.z[p] = 0;
            for (int i = 0; i < 4; ++i) {
                pt.x[p] += l[i] * m.x[c[i]];
                pt.y[p] += l[i] * m.y[c[i]];
                pt.z[p] += l[i] * m.z[c[i]];
                pt.w[4 * p + i] = l[i];
            }
            pt.vx[p] = pt.vy[p] = pt.vz[p] = 0;
            pt.volume[p] = volume;
            pt.mass[p] = volume * s.material.density;
            for (auto& sg : pt.stress) sg[p] = 0;
            pt.elem[p] = static_cast<std::uint32_t>(e);
        }
    }
    // Ids by position (x, then y, then z): the same particle gets the same id whatever the
    // grid's ordering, since the seeding points are computed the same way in every ordering
    // (corners keep their order within an element), so runs in different orders compare by id.
    std::vector<std::uint32_t> rank(pt.size());
    for (std::size_t p = 0; p < rank.size(); ++p) rank[p] = static_cast<std::uint32_t>(p);
    std::sort(rank.begin(), rank.end(), [&](std::uint32_t a, std::uint32_t b) {
        if (pt.x[a] != pt.x[b]) return pt.x[a] < pt.x[b];
        if (pt.y[a] != pt.y[b]) return pt.y[a] < pt.y[b];
        return pt.z[a] < pt.z[b];
    });
    for (std::size_t r = 0; r < rank.size(); ++r) pt.id[rank[r]] = static_cast<std::uint32_t>(r);
    st.plan = plan_scatter(grid, strategy, threads);
    st.grid = std::move(grid);
    if (arena) {
        if (strategy == Strategy::colour || strategy == Strategy::partition) {
            // Written by locate's serial counting sort, read by the scatters' element runs, which
            // the partition balances by particles: about the particles' own split.
            const std::size_t n = pt.size();
            std::uint32_t* const order = arena->allocate<std::uint32_t>("bins-order", n);
            const std::int64_t count = static_cast<std::int64_t>(n);
#pragma omp parallel
            {
                const Block b = my_block(count);
                std::fill(order + b.lo, order + b.hi, 0u);
            }
            st.bins.order = Array<std::uint32_t>::placed(order, n);
        }
        locate(st);  // node_hi, for the nodes' first touch
        place_grid_arrays(st, *arena);
    } else {
        st.nodes.assign(st.grid.nodes(), NodeState{});
        locate(st);
    }
    return st;
}

Settings case_settings(const std::string& name) { return cases().at(name).what.settings; }

void check_particle_order(const std::string& name) { particle_orders().at(name); }

Energy energy(const State& st) {
    const Particles& p = st.particles;
    const Material& mat = st.settings.material;
    const double* g = st.settings.gravity;
    Energy e;
    e.kinetic = totals(p).kinetic;
    for (std::size_t i = 0; i < p.size(); ++i) {
        e.potential -= p.mass[i] * (g[0] * p.x[i] + g[1] * p.y[i] + g[2] * p.z[i]);
        if (mat.model == Material::Model::fluid) {
            const double j = p.volume[i] * mat.density / p.mass[i];
            if (j < 1) e.internal += p.mass[i] / mat.density * mat.bulk_modulus() * (j - 1 - std::log(j));
            continue;
        }
        const double sx = p.stress[0][i], sy = p.stress[1][i], sz = p.stress[2][i];
        const double shear =
            p.stress[3][i] * p.stress[3][i] + p.stress[4][i] * p.stress[4][i] + p.stress[5][i] * p.stress[5][i];
        const double tr = sx + sy + sz, ss = sx * sx + sy * sy + sz * sz + 2 * shear;
        e.internal += 0.5 * p.volume[i] * ((1 + mat.poisson) * ss - mat.poisson * tr * tr) / mat.young;
    }
    return e;
}

double same_element_share(const Particles& p) {
    const std::int64_t n = static_cast<std::int64_t>(p.size());
    if (n < 2) return 0;
    const std::uint32_t* const e = p.elem.data();
    std::int64_t same = 0;  // a count: the same share on any number of threads
#pragma omp parallel for schedule(static) reduction(+ : same)
    for (std::int64_t i = 1; i < n; ++i) same += e[i] == e[i - 1] ? 1 : 0;
    return static_cast<double>(same) / static_cast<double>(n - 1);
}

Locality locality(const State& st) {
    const Particles& p = st.particles;
    const std::uint32_t* curve = st.grid.curve.data();
    Locality l;
    if (p.size() < 2) return l;
    double gap = 0;
    std::size_t same = 0;
    for (std::size_t i = 1; i < p.size(); ++i) {
        const std::uint32_t a = curve[p.elem[i - 1]], b = curve[p.elem[i]];
        gap += a > b ? a - b : b - a;
        same += a == b ? 1 : 0;
    }
    const double pairs = static_cast<double>(p.size() - 1);
    l.mean_gap = gap / pairs;
    l.same_element = static_cast<double>(same) / pairs;
    return l;
}

Totals totals(const Particles& p) {
    Totals t;
    for (std::size_t i = 0; i < p.size(); ++i) {
        const double m = p.mass[i];
        t.mass += m;
        t.momentum[0] += m * p.vx[i];
        t.momentum[1] += m * p.vy[i];
        t.momentum[2] += m * p.vz[i];
        t.kinetic += 0.5 * m * (p.vx[i] * p.vx[i] + p.vy[i] * p.vy[i] + p.vz[i] * p.vz[i]);
    }
    return t;
}

double front(const Particles& p) { return p.x.empty() ? 0 : *std::max_element(p.x.begin(), p.x.end()); }

}  // namespace suite::mpm
