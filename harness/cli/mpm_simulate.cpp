#include "harness/cli/mpm_simulate.hpp"

#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>

#include "harness/common/units.hpp"
#include "kernels/mpm/kernel_checks.hpp"

namespace suite {

// Names in this file carry an mpm_ prefix: harness/cli compiles as one unit (CMakeLists.txt).
namespace {

using MpmClock = std::chrono::steady_clock;
double mpm_seconds(MpmClock::time_point a, MpmClock::time_point b) { return std::chrono::duration<double>(b - a).count(); }

std::atomic<int> mpm_stop_signal{0};
void mpm_on_signal(int sig) { mpm_stop_signal.store(sig); }

std::string mpm_g(double v) {
    char b[32];
    std::snprintf(b, sizeof b, "%.6g", v);
    return b;
}

// The first particle whose position or velocity is not finite, or that lies outside the grid's
// box; "" when there is none. g2p pulls a position that crossed a wall back onto it, so a
// particle outside the box (or a NaN, which no comparison keeps inside) means a broken step.
std::string mpm_first_bad_particle(const mpm::State& st) {
    const mpm::Particles& p = st.particles;
    const double* lo = st.grid.lo;
    const double* hi = st.grid.hi;
    for (std::size_t i = 0; i < p.size(); ++i) {
        const double x[3] = {p.x[i], p.y[i], p.z[i]}, v[3] = {p.vx[i], p.vy[i], p.vz[i]};
        const std::string who = "particle " + std::to_string(p.id[i]);
        const auto triple = [](const double* a) { return "(" + mpm_g(a[0]) + ", " + mpm_g(a[1]) + ", " + mpm_g(a[2]) + ")"; };
        if (!std::isfinite(x[0]) || !std::isfinite(x[1]) || !std::isfinite(x[2])) return who + "'s position " + triple(x) + " is not finite";
        if (!std::isfinite(v[0]) || !std::isfinite(v[1]) || !std::isfinite(v[2])) return who + "'s velocity " + triple(v) + " is not finite";
        for (int a = 0; a < 3; ++a)
            if (!(x[a] >= lo[a] && x[a] <= hi[a]))
                return who + " at " + triple(x) + " is outside the box [" + mpm_g(lo[0]) + "," + mpm_g(lo[1]) + "," + mpm_g(lo[2]) + "] to [" +
                       mpm_g(hi[0]) + "," + mpm_g(hi[1]) + "," + mpm_g(hi[2]) + "]";
    }
    return "";
}

// The most energy gravity can give the particles from where they are: Σ m (-g) · (x - the wall
// gravity pulls towards). The material starts at rest and unstressed and the walls do no work,
// so a kinetic energy above it (with a margin for the scheme's error) was made by the time
// stepping: an unstable step, which the walls' clamping can keep finite for a long time.
double mpm_releasable_energy(const mpm::State& st) {
    const mpm::Particles& p = st.particles;
    const double* g = st.settings.gravity;
    const std::vector<double>* axes[3] = {&p.x, &p.y, &p.z};
    double e = 0;
    for (std::size_t i = 0; i < p.size(); ++i)
        for (int a = 0; a < 3; ++a) {
            const double wall = g[a] < 0 ? st.grid.lo[a] : st.grid.hi[a];
            e += p.mass[i] * -g[a] * ((*axes[a])[i] - wall);
        }
    return e;
}
constexpr double mpm_energy_margin = 1.5;

// Each particle's mass indexed by its id, after checking that the ids are a permutation of
// 0..n-1; `why` says what is wrong when they are not.
std::vector<double> mpm_mass_by_id(const mpm::Particles& p, std::string& why) {
    const std::size_t n = p.size();
    std::vector<double> mass(n, 0);
    std::vector<char> seen(n, 0);
    for (std::size_t i = 0; i < n; ++i) {
        const std::uint32_t id = p.id[i];
        if (id >= n || seen[id]) {
            why = "the particle ids are not a permutation of 0.." + std::to_string(n - 1) + " (id " + std::to_string(id) + " at position " +
                  std::to_string(i) + ")";
            return {};
        }
        seen[id] = 1;
        mass[id] = p.mass[i];
    }
    return mass;
}


// The progress line: rewritten in place on a terminal (at most ten times a second), otherwise a
// line at every tenth of the run, so that a log shows progress without a line a step.
class MpmProgress {
public:
    MpmProgress(bool quiet, std::uint64_t steps, std::size_t particles)
        : on_(!quiet), tty_(isatty(STDERR_FILENO) != 0), steps_(steps), particles_(particles) {}

    void update(const mpm::State& st, double front, double stepping_s) {
        if (!on_) return;
        const std::uint64_t k = st.steps;
        const auto now = MpmClock::now();
        if (tty_) {
            if (k != steps_ && mpm_seconds(last_, now) < 0.1) return;
        } else {
            // The first step at or past the next tenth of the run.
            if (k * 10 < next_tenth_ * steps_) return;
            while (next_tenth_ <= 10 && k * 10 >= next_tenth_ * steps_) ++next_tenth_;
        }
        last_ = now;
        const double rate = stepping_s > 0 ? static_cast<double>(particles_) * static_cast<double>(k) / stepping_s : 0;
        std::fprintf(stderr, "%sstep %llu/%llu  t = %.4g s  front %.4f m  %.3g particle-steps/s%s", tty_ ? "\r\033[K" : "",
                     static_cast<unsigned long long>(k), static_cast<unsigned long long>(steps_), st.time, front, rate, tty_ ? "" : "\n");
        std::fflush(stderr);
        shown_ = true;
    }
    // Clears the line on a terminal, so that what follows starts on a clean one.
    void finish() {
        if (on_ && tty_ && shown_) std::fprintf(stderr, "\r\033[K");
        std::fflush(stderr);
    }

private:
    bool on_, tty_, shown_ = false;
    std::uint64_t steps_;
    std::size_t particles_;
    std::uint64_t next_tenth_ = 1;
    MpmClock::time_point last_{};
};

// SIGINT and SIGTERM set a flag for the duration of the loop, so that an interrupted run still
// writes what it did; a second one ends the program at once (SA_RESETHAND).
class MpmSignals {
public:
    MpmSignals() {
        mpm_stop_signal.store(0);
        struct sigaction sa {};
        sa.sa_handler = mpm_on_signal;
        sa.sa_flags = SA_RESETHAND;
        sigemptyset(&sa.sa_mask);
        sigaction(SIGINT, &sa, &old_int_);
        sigaction(SIGTERM, &sa, &old_term_);
    }
    ~MpmSignals() {
        sigaction(SIGINT, &old_int_, nullptr);
        sigaction(SIGTERM, &old_term_, nullptr);
    }
    MpmSignals(const MpmSignals&) = delete;
    MpmSignals& operator=(const MpmSignals&) = delete;

private:
    struct sigaction old_int_ {}, old_term_ {};
};

}  // namespace

std::string mpm_snapshot_name(std::uint64_t step) {
    char b[48];
    std::snprintf(b, sizeof b, "particles_%06llu.vtu", static_cast<unsigned long long>(step));
    return b;
}

MpmOutcome mpm_simulate(mpm::State& st, const mpm::Setup& setup, const MpmRunSettings& settings, const OutputDir& out) {
    MpmOutcome r;
    const MpmSignals signals;
    std::string why;
    const std::vector<double> mass0 = mpm_mass_by_id(st.particles, why);
    if (!why.empty()) throw std::logic_error("suite mpm: the state as built: " + why);
    r.mass_initial = mpm::compensated_sum(mass0);
    const auto snapshot = [&] {
        const std::string name = mpm_snapshot_name(st.steps);
        out.write(name, mpm::particles_vtu(st.particles));
        r.snapshots.push_back({name, st.time});
        r.snapshot_steps.push_back(st.steps);
    };
    const auto row = [&] {
        r.rows.push_back({st.steps, st.time, mpm::front(st.particles), mpm::totals(st.particles).kinetic});
    };
    MpmProgress progress(settings.quiet, settings.steps, st.particles.size());
    MpmCheck finite{"finite and inside the box", true, ""};
    MpmCheck energy{"energy bound", true, ""};
    const double releasable = mpm_releasable_energy(st);
    double peak = 0;
    std::uint64_t energy_steps = 0;
    const auto t0 = MpmClock::now();
    row();
    if (settings.vtk_every > 0) snapshot();
    for (std::uint64_t k = 1; k <= settings.steps; ++k) {
        if (const int sig = mpm_stop_signal.load()) {
            r.signal = sig;
            break;
        }
        const auto s0 = MpmClock::now();
        try {
            mpm::advance(st, setup);
        } catch (const std::exception& e) {
            // A particle lost by the walk (a NaN position walks forever) ends the run as a failed check.
            finite = {finite.name, false, "step " + std::to_string(k) + ": " + e.what()};
            break;
        }
        r.stepping_s += mpm_seconds(s0, MpmClock::now());
        r.steps_done = k;
        row();  // the step that fails a check too: its front and energy may show how
        if (const std::string bad = mpm_first_bad_particle(st); !bad.empty()) {
            finite = {finite.name, false, "after step " + std::to_string(k) + " (t = " + mpm_g(st.time) + " s): " + bad};
            break;
        }
        const double kinetic = r.rows.back().kinetic;
        peak = std::max(peak, kinetic);
        energy_steps = k;
        if (kinetic > mpm_energy_margin * releasable) {
            energy = {energy.name, false,
                      "after step " + std::to_string(k) + " (t = " + mpm_g(st.time) + " s): the kinetic energy " + mpm_g(kinetic) + " J is more than " +
                          mpm_g(mpm_energy_margin) + " times the " + mpm_g(releasable) +
                          " J gravity can release from the start: the time stepping is unstable (give a smaller --dt or --courant)"};
            break;
        }
        if (settings.vtk_every > 0 && (k % settings.vtk_every == 0 || k == settings.steps)) snapshot();
        progress.update(st, r.rows.back().front, r.stepping_s);
    }
    // An interrupted run keeps its last state too, for a look at where it stopped.
    if (r.signal && settings.vtk_every > 0 && r.snapshot_steps.back() != st.steps) snapshot();
    progress.finish();
    r.wall_s = mpm_seconds(t0, MpmClock::now());
    if (finite.passed)
        finite.detail = "every particle's position and velocity finite and inside the box after each of " + std::to_string(r.steps_done) + " step(s)";
    r.checks.push_back(finite);
    if (energy.passed)
        energy.detail = "the kinetic energy peaked at " + mpm_g(peak) + " J, at most " + mpm_g(mpm_energy_margin) + " times the " + mpm_g(releasable) +
                        " J gravity can release (checked after each of " + std::to_string(energy_steps) + " step(s))";
    r.checks.push_back(energy);
    for (const auto& c : r.checks)
        if (!c.passed) {
            r.failure = c.name + ": " + c.detail;
            return r;
        }

    // Masses never change: each particle's must be its starting one exactly, whatever the
    // reorderings did to the particles' order (so the sums are taken in id order).
    MpmCheck mass{"mass", true, ""};
    const std::vector<double> mass1 = mpm_mass_by_id(st.particles, why);
    r.mass_final = mass1.empty() ? NAN : mpm::compensated_sum(mass1);
    std::size_t changed = 0;
    for (std::size_t i = 0; i < mass1.size(); ++i) changed += mass1[i] != mass0[i] ? 1 : 0;
    if (!why.empty()) mass = {mass.name, false, why};
    else if (changed > 0)
        mass = {mass.name, false, std::to_string(changed) + " particle(s) changed mass; total " + mpm_g(r.mass_initial) + " kg -> " + mpm_g(r.mass_final) + " kg"};
    else mass.detail = "every particle's mass is its initial one exactly; total " + format_number(r.mass_final) + " kg";
    r.checks.push_back(mass);

    // A P2G of the final particles, with the run's strategy: the nodes must receive all of it.
    mpm::p2g(st);
    std::vector<double> node_mass(st.node_hi);
    for (std::uint32_t n = 0; n < st.node_hi; ++n) node_mass[n] = st.nodes[n].m;
    r.nodal_mass = mpm::compensated_sum(node_mass);
    r.nodal_error = std::fabs(r.nodal_mass - r.mass_initial) / r.mass_initial;
    MpmCheck nodal{"nodal mass", r.nodal_error <= 1e-12, ""};
    nodal.detail = "a P2G of the final particles puts " + format_number(r.nodal_mass) + " kg on the nodes, " + mpm_g(r.nodal_error) +
                   " relative to the particles' total (at most 1e-12)";
    r.checks.push_back(nodal);
    for (const auto& c : r.checks)
        if (!c.passed && r.failure.empty()) r.failure = c.name + ": " + c.detail;
    return r;
}

}  // namespace suite
