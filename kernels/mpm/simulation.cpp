#include "kernels/mpm/simulation.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <map>
#include <stdexcept>

#include "harness/common/units.hpp"
#include "kernels/mpm/free_fall.hpp"
#include "kernels/mpm/kernel_checks.hpp"

namespace suite::mpm {

namespace {

using Clock = std::chrono::steady_clock;
double seconds_between(Clock::time_point a, Clock::time_point b) {
    return std::chrono::duration<double>(b - a).count();
}

std::string g(double v) {
    char b[32];
    std::snprintf(b, sizeof b, "%.6g", v);
    return b;
}
// For the functions where g is gravity.
std::string g6(double v) { return g(v); }

// The first particle whose position or velocity is not finite, or that lies outside the grid's
// box; "" when there is none. g2p pulls a position that crossed a wall back onto it, so a
// particle outside the box (or a NaN, which no comparison keeps inside) means a broken step.
std::string first_bad_particle(const State& st) {
    const Particles& p = st.particles;
    const double* lo = st.grid.lo;
    const double* hi = st.grid.hi;
    for (std::size_t i = 0; i < p.size(); ++i) {
        const double x[3] = {p.x[i], p.y[i], p.z[i]}, v[3] = {p.vx[i], p.vy[i], p.vz[i]};
        // The words are made only for a particle that fails (this runs after every step).
        const auto who = [&p, i] { return "particle " + std::to_string(p.id[i]); };
        const auto triple = [](const double* a) {
            char b[96];
            std::snprintf(b, sizeof b, "(%.6g, %.6g, %.6g)", a[0], a[1], a[2]);
            return std::string(b);
        };
        if (!std::isfinite(x[0]) || !std::isfinite(x[1]) || !std::isfinite(x[2]))
            return who() + "'s position " + triple(x) + " is not finite";
        if (!std::isfinite(v[0]) || !std::isfinite(v[1]) || !std::isfinite(v[2]))
            return who() + "'s velocity " + triple(v) + " is not finite";
        for (int a = 0; a < 3; ++a)
            if (!(x[a] >= lo[a] && x[a] <= hi[a]))
                return who() + " at " + triple(x) + " is outside the box [" + g(lo[0]) + "," + g(lo[1]) + "," +
                       g(lo[2]) + "] to [" + g(hi[0]) + "," + g(hi[1]) + "," + g(hi[2]) + "]";
    }
    return "";
}

// The most energy gravity can give the particles from where they are: Σ m (-g) · (x - the wall
// gravity pulls towards). The material starts at rest and unstressed and the walls do no work,
// so a kinetic energy above it (with a margin for the scheme's error) was made by the time
// stepping: an unstable step, which the walls' clamping can keep finite for a long time.
double releasable_energy(const State& st) {
    const Particles& p = st.particles;
    const double* g = st.settings.gravity;
    const Array<double>* axes[3] = {&p.x, &p.y, &p.z};
    double e = 0;
    for (std::size_t i = 0; i < p.size(); ++i)
        for (int a = 0; a < 3; ++a) {
            const double wall = g[a] < 0 ? st.grid.lo[a] : st.grid.hi[a];
            e += p.mass[i] * -g[a] * ((*axes[a])[i] - wall);
        }
    return e;
}
constexpr double energy_margin = 1.5;

constexpr double column_tolerance = 0.05;

// The column's check (Outcome's settlement_* and stress_rms): the one-dimensional answer for a
// layer of height H on a frictionless floor between frictionless walls, under gravity g: it
// strains in z alone, σzz(z0) = -ρ g (H - z0) (the weight above, whatever the deformation),
// and the top settles by ρ g H² / (2 M), M = E (1 - ν) / ((1 + ν)(1 - 2ν)), the constrained
// modulus (linear, small strain: the measured top strain of 3.6 % at the foot makes the exact
// hypoelastic answer about 1 % smaller, inside the tolerance).
void column_check(const State& st, double top_z, const std::vector<double>& z0, const std::vector<char>& top,
                  Outcome& r) {
    const Material& m = st.settings.material;
    const double g = std::fabs(st.settings.gravity[2]), rho = m.density;
    const double modulus = m.young * (1 - m.poisson) / ((1 + m.poisson) * (1 - 2 * m.poisson));
    // H: the seeded material's height, to the top of its highest element (elements join the
    // region by their centroid, so the region's own top need not be the material's).
    const double h = top_z - st.settings.region.lo[2];
    double exact = 0, n = 0;
    for (std::size_t id = 0; id < z0.size(); ++id)
        if (top[id]) {
            const double z = z0[id] - st.settings.region.lo[2];
            exact += rho * g * (h * z - z * z / 2) / modulus, n += 1;
        }
    r.settlement_exact = exact / n;
    // The static integrator's every step is an equilibrium: settled, as a damped run's end is.
    const bool damped = st.settings.damping > 0 || st.settings.integrator == Integrator::quasi_static;
    // Damped: the settled state, the last tenth of the run; undamped: the oscillation's mean.
    const std::size_t first = damped ? r.rows.size() - std::max<std::size_t>(1, (r.rows.size() - 1) / 10) : 1;
    double sum = 0, count = 0;
    for (std::size_t k = first; k < r.rows.size(); ++k) sum += r.rows[k].settlement, count += 1;
    r.settlement_measured = sum / count;
    r.settlement_error = (r.settlement_measured - r.settlement_exact) / r.settlement_exact;
    if (damped) {
        const Particles& p = st.particles;
        double ss = 0;
        for (std::size_t i = 0; i < p.size(); ++i) {
            const double d = p.stress[2][i] + rho * g * (h - (z0[p.id[i]] - st.settings.region.lo[2]));
            ss += d * d;
        }
        r.stress_rms = std::sqrt(ss / static_cast<double>(p.size())) / (rho * g * h);
        // The profile without the sawtooth inside an element: a linear element has one strain, so
        // its particles' stress can meet the linear exact profile at one height only. Averaged over
        // a horizontal layer of elements (those whose lowest corner is at the same height: one
        // layer of the box's cubes), the mean σzz against the exact at the layer's particles' mean
        // starting height.
        std::map<double, std::array<double, 3>> layer;  // lowest corner's z: Σ σzz, Σ z0, count
        const std::uint32_t* conn = st.grid.mesh.conn.data();
        const std::vector<double>& gz = st.grid.mesh.z;
        for (std::size_t i = 0; i < p.size(); ++i) {
            const std::uint32_t* c = conn + 4 * static_cast<std::size_t>(p.elem[i]);
            const double low = std::round(std::min({gz[c[0]], gz[c[1]], gz[c[2]], gz[c[3]]}) * 1e9) / 1e9;
            std::array<double, 3>& l = layer[low];
            l[0] += p.stress[2][i], l[1] += z0[p.id[i]], l[2] += 1;
        }
        double se = 0;
        for (const auto& [low, l] : layer) {
            const double d = l[0] / l[2] + rho * g * (h - (l[1] / l[2] - st.settings.region.lo[2]));
            se += l[2] * d * d;
        }
        r.stress_profile = std::sqrt(se / static_cast<double>(p.size())) / (rho * g * h);
    }
    Check c{"column", std::fabs(r.settlement_error) <= column_tolerance, ""};
    c.detail =
        std::string(damped ? (st.settings.damping > 0 ? "settled (damped; the mean of the last tenth of the steps)"
                                                      : "static (the mean of the last tenth of the steps)")
                           : "the mean over the run (undamped)") +
        ", the top layer sank " + g6(r.settlement_measured) + " m against the one-dimensional " +
        g6(r.settlement_exact) + " m: " + g6(100 * r.settlement_error) + " % (at most " + g6(100 * column_tolerance) +
        " %)" +
        (damped ? "; σzz against -ρ g (H - z0): RMS " + g6(100 * r.stress_rms) + " % of ρ g H, each layer's mean " +
                      g6(100 * r.stress_profile) + " %"
                : "");
    r.checks.push_back(c);
}

}  // namespace

std::string snapshot_name(std::uint64_t step) {
    char b[48];
    std::snprintf(b, sizeof b, "particles_%06llu.vtu", static_cast<unsigned long long>(step));
    return b;
}

Outcome simulate(State& st, const Setup& setup, const SimulationSettings& run, const SimulationHooks& hooks) {
    if (run.vtk_every > 0 && !hooks.snapshot)
        throw std::logic_error("mpm::simulate: snapshots asked for and no hook to take them");
    Outcome r;
    std::string why;
    const std::vector<double> mass0 = masses_by_id(st.particles, why);
    if (!why.empty()) throw std::logic_error("mpm::simulate: the state as built: " + why);
    r.mass_initial = compensated_sum(mass0);
    const auto snapshot = [&] {
        const std::string name = snapshot_name(st.steps);
        hooks.snapshot(name, particles_vtu(st.particles));
        r.snapshots.push_back({name, st.time});
        r.snapshot_steps.push_back(st.steps);
    };
    // The column: each particle's starting height by id, and which ids form the top layer.
    std::vector<double> z0;
    std::vector<char> top;
    double top_z = -INFINITY;  // the top of the highest element holding material
    if (run.column) {
        const Particles& p = st.particles;
        const std::uint32_t* conn = st.grid.mesh.conn.data();
        for (std::size_t i = 0; i < p.size(); ++i)
            for (int c = 0; c < 4; ++c)
                top_z = std::max(top_z, st.grid.mesh.z[conn[4 * static_cast<std::size_t>(p.elem[i]) + c]]);
        z0.resize(p.size());
        top.assign(p.size(), 0);
        double highest = -INFINITY;
        for (std::size_t i = 0; i < p.size(); ++i) z0[p.id[i]] = p.z[i], highest = std::max(highest, p.z[i]);
        for (std::size_t i = 0; i < p.size(); ++i) top[i] = z0[i] >= highest - 1e-9 * (st.grid.hi[2] - st.grid.lo[2]);
    }
    const auto settlement = [&] {
        if (!run.column) return static_cast<double>(NAN);
        const Particles& p = st.particles;
        double d = 0, n = 0;
        for (std::size_t i = 0; i < p.size(); ++i)
            if (top[p.id[i]]) d += z0[p.id[i]] - p.z[i], n += 1;
        return d / n;
    };
    const auto row = [&] {
        const Energy e = energy(st);
        const bool reordered = st.order.count > 0 && st.order.last_step == st.steps;
        r.rows.push_back({st.steps, st.time, front(st.particles), e.kinetic, st.steps == 0 ? 0.0 : st.dt, settlement(),
                          r.stepping_s, e.potential, e.internal, locality(st),
                          reordered ? st.order.last_cause : ReorderCause::none});
    };
    Check finite{"finite and inside the box", true, ""};
    Check energy{"energy bound", true, ""};
    const double releasable = releasable_energy(st);
    double peak = 0;
    std::uint64_t energy_steps = 0;
    // A fluid: the total energy may only fall (viscosity, the walls' inelastic stops) but for the
    // scheme's error, here 5 % of what gravity can release; and the front stays behind Ritter's
    // dam-break front x = L0 + 2 sqrt(g H) t (frictionless shallow water, the upper bound of every
    // measured front), L0 and H the seeded column's outermost and highest particle, by one
    // element's smallest altitude of slack (the material reaches past its outermost particle).
    const bool fluid = st.settings.material.model == Material::Model::fluid;
    Check total{"total energy", true, ""}, ritter{"Ritter front", true, ""}, solver{"Newton", true, ""};
    const bool implicit = st.settings.integrator != Integrator::explicit_step;
    // Average acceleration conserves a linear problem's energy, so an implicit run's total is
    // held to the fluid's bound too (the fluid's because its stepping may not make energy).
    const bool bounded = fluid || st.settings.integrator == Integrator::implicit;
    const double total_margin = 0.05;
    const double gravity = std::fabs(st.settings.gravity[2]);
    // The column as seeded (elements join it by their centroid, so its faces are not exactly the region's).
    const double l0 = front(st.particles);
    double h0 = 0;
    for (double z : st.particles.z) h0 = std::max(h0, z - st.grid.lo[2]);
    double total_peak = -INFINITY, ritter_gap = -INFINITY;
    const auto t0 = Clock::now();
    row();
    const double e0 = r.rows.front().kinetic + r.rows.front().potential + r.rows.front().internal;
    // A state that starts moving (a test's, or a restart) may have that much more to spend.
    const double kinetic0 = r.rows.front().kinetic;
    if (run.vtk_every > 0) snapshot();
    FreeFall fall(st, run.free_fall && st.settings.integrator == Integrator::explicit_step && st.settings.damping == 0);
    for (std::uint64_t k = 1; k <= run.steps; ++k) {
        if (const int sig = run.stop ? run.stop->load() : 0) {
            r.signal = sig;
            break;
        }
        const auto s0 = Clock::now();
        try {
            advance(st, setup);
        } catch (const std::exception& e) {
            // A particle lost by the walk (a NaN position walks forever) ends the run as a failed check.
            finite = {finite.name, false, "step " + std::to_string(k) + ": " + e.what()};
            break;
        }
        r.stepping_s += seconds_between(s0, Clock::now());
        if (!st.implicit.failure.empty()) {
            solver = {solver.name, false,
                      "step " + std::to_string(k) + " (t = " + g(st.time) + " s): " + st.implicit.failure};
            r.solver_failed = true;
            break;
        }
        r.steps_done = k;
        fall.observe(st);
        row();  // the step that fails a check too: its front and energy may show how
        if (const std::string bad = first_bad_particle(st); !bad.empty()) {
            finite = {finite.name, false, "after step " + std::to_string(k) + " (t = " + g(st.time) + " s): " + bad};
            break;
        }
        if (bounded) {
            const FrontRow& now = r.rows.back();
            const double e = now.kinetic + now.potential + now.internal;
            total_peak = std::max(total_peak, e - e0);
            if (e > e0 + total_margin * releasable) {
                total = {total.name, false,
                         "after step " + std::to_string(k) + " (t = " + g(st.time) + " s): the total energy " + g(e) +
                             " J is " + g(e - e0) + " J above its start, more than " + g(total_margin) + " of the " +
                             g(releasable) + " J gravity can release: the time stepping made energy (give a smaller " +
                             (implicit ? "--dt" : "--courant") + ")"};
                break;
            }
        }
        if (fluid) {
            const FrontRow& now = r.rows.back();
            const double bound = l0 + 2 * std::sqrt(gravity * h0) * st.time + st.grid.min_length;
            ritter_gap = std::max(ritter_gap, now.front - bound);
            if (now.front > bound && bound < st.grid.hi[0]) {
                ritter = {ritter.name, false,
                          "after step " + std::to_string(k) + " (t = " + g(st.time) + " s): the front " + g(now.front) +
                              " m is ahead of Ritter's " + g(bound - st.grid.min_length) +
                              " m (L0 + 2 sqrt(g H) t) by more than one element's altitude " + g(st.grid.min_length) +
                              " m"};
                break;
            }
        }
        const double kinetic = r.rows.back().kinetic;
        peak = std::max(peak, kinetic);
        energy_steps = k;
        if (kinetic > energy_margin * (releasable + kinetic0)) {
            energy = {energy.name, false,
                      "after step " + std::to_string(k) + " (t = " + g(st.time) + " s): the kinetic energy " +
                          g(kinetic) + " J is more than " + g(energy_margin) + " times the " + g(releasable) +
                          " J gravity can release from the start" +
                          (kinetic0 > 0 ? " plus the starting " + g(kinetic0) + " J" : std::string()) +
                          ": the time stepping is unstable (give a smaller --dt or --courant)"};
            break;
        }
        if (run.vtk_every > 0 && (k % run.vtk_every == 0 || k == run.steps)) snapshot();
        if (hooks.progress) hooks.progress(st, r.rows.back().front, r.stepping_s);
    }
    // An interrupted run keeps its last state too, for a look at where it stopped.
    if (r.signal && run.vtk_every > 0 && r.snapshot_steps.back() != st.steps) snapshot();
    r.wall_s = seconds_between(t0, Clock::now());
    if (finite.passed)
        finite.detail = "every particle's position and velocity finite and inside the box after each of " +
                        std::to_string(r.steps_done) + " step(s)";
    r.checks.push_back(finite);
    if (energy.passed)
        energy.detail = "the kinetic energy peaked at " + g(peak) + " J, at most " + g(energy_margin) + " times the " +
                        g(releasable) + " J gravity can release" +
                        (kinetic0 > 0 ? " plus the starting " + g(kinetic0) + " J" : std::string()) +
                        " (checked after each of " + std::to_string(energy_steps) + " step(s))";
    r.checks.push_back(energy);
    if (implicit) {
        const ImplicitStats& im = st.implicit;
        if (solver.passed)
            solver.detail = "converged in every step: at most " + std::to_string(im.max_newton) +
                            " Newton iteration(s), " + std::to_string(im.newton) + " linear solve(s) in all (" +
                            std::to_string(im.solver_iterations) + " CG iterations), the worst final ||r|| / ||r0|| " +
                            g(im.worst_residual);
        r.checks.push_back(solver);
    }
    if (bounded) {
        if (total.passed)
            total.detail = "the total energy (kinetic, potential, internal) at most " + g(std::max(total_peak, 0.0)) +
                           " J above its start " + g(e0) + " J, within " + g(total_margin) + " of the " +
                           g(releasable) + " J gravity can release (after each of " + std::to_string(r.steps_done) +
                           " step(s))";
        r.checks.push_back(total);
    }
    if (fluid) {
        if (ritter.passed)
            ritter.detail =
                "the front never ahead of L0 + 2 sqrt(g H) t (L0 = " + g(l0) + " m, H = " + g(h0) +
                " m) by more than one element's altitude " + g(st.grid.min_length) + " m (at its closest " +
                (ritter_gap + st.grid.min_length <= 0 ? g(-(ritter_gap + st.grid.min_length)) + " m behind it)"
                                                      : g(ritter_gap + st.grid.min_length) + " m ahead of it)");
        r.checks.push_back(ritter);
    }
    for (const auto& c : r.checks)
        if (!c.passed) {
            r.failure = c.name + ": " + c.detail;
            return r;
        }

    if (run.column && r.steps_done > 0) column_check(st, top_z, z0, top, r);
    if (run.free_fall) r.checks.push_back(free_fall_check(fall, st, r));

    // Masses never change: each particle's must be its starting one exactly, whatever the
    // reorderings did to the particles' order (so the sums are taken in id order).
    Check mass{"mass", true, ""};
    const std::vector<double> mass1 = masses_by_id(st.particles, why);
    r.mass_final = mass1.empty() ? NAN : compensated_sum(mass1);
    std::size_t changed = 0;
    for (std::size_t i = 0; i < mass1.size(); ++i) changed += mass1[i] != mass0[i] ? 1 : 0;
    if (!why.empty())
        mass = {mass.name, false, why};
    else if (changed > 0)
        mass = {mass.name, false,
                std::to_string(changed) + " particle(s) changed mass; total " + g(r.mass_initial) + " kg -> " +
                    g(r.mass_final) + " kg"};
    else
        mass.detail = "every particle's mass is its initial one exactly; total " + format_number(r.mass_final) + " kg";
    r.checks.push_back(mass);

    // A P2G of the final particles, with the run's strategy: the nodes must receive all of it.
    p2g(st);
    std::vector<double> node_mass(st.node_hi);
    for (std::uint32_t n = 0; n < st.node_hi; ++n) node_mass[n] = st.nodes[n].m;
    r.nodal_mass = compensated_sum(node_mass);
    r.nodal_error = std::fabs(r.nodal_mass - r.mass_initial) / r.mass_initial;
    Check nodal{"nodal mass", r.nodal_error <= 1e-12, ""};
    nodal.detail = "a P2G of the final particles puts " + format_number(r.nodal_mass) + " kg on the nodes, " +
                   g(r.nodal_error) + " relative to the particles' total (at most 1e-12)";
    r.checks.push_back(nodal);
    for (const auto& c : r.checks)
        if (!c.passed && r.failure.empty()) r.failure = c.name + ": " + c.detail;
    return r;
}

std::uint64_t snapshot_count(std::uint64_t steps, std::uint64_t every) {
    if (every == 0) return 0;
    return 1 + steps / every + (steps % every != 0 ? 1 : 0);
}

}  // namespace suite::mpm
