#pragma once
// The explicit MPM run as a simulation (what `suite mpm` runs, callable without it): the steps of
// mpm::advance with the checks after each (every particle's position and velocity finite and
// inside the box; the kinetic energy within what gravity can release: an unstable step shows
// there first; for a fluid also the total energy at most its start plus a margin, and the front
// never ahead of Ritter's shallow-water front), the snapshots' schedule, and the checks at the end (each particle's
// mass what it was at the start, bit for bit; a P2G of the final particles puts on the nodes the particles' total mass
// to 1e-12). It writes nothing itself: snapshots and progress go to the caller's hooks. It stops at the first failed
// check or when the caller's stop flag is raised, and the outcome holds what was done either way.
#include <atomic>
#include <cmath>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "kernels/mpm/mpm.hpp"
#include "kernels/mpm/vtk.hpp"

namespace suite::mpm {

struct SimulationSettings {
    // The column case: measure the settlement of the top particle layer and the stress against
    // the one-dimensional answer (a check at the end; docs/mpm.md, "The column").
    bool column = false;
    bool free_fall = false;  // the free-fall case: the fall before a wall acts against the exact one (free_fall.hpp)
    std::uint64_t steps = 1000;
    std::uint64_t vtk_every = 50;            // 0: no snapshots
    const std::atomic<int>* stop = nullptr;  // non-zero (a signal's number): stop before the next step
};

struct SimulationHooks {
    // Each snapshot: particles_SSSSSS.vtu and its text (particles_vtu). Needed when vtk_every > 0.
    std::function<void(const std::string& name, const std::string& vtu)> snapshot;
    // After each step that passed its checks: the state, its front, the seconds of stepping so far.
    std::function<void(const State& st, double front, double stepping_s)> progress;
};

// One row of front.csv: after `step` steps.
struct FrontRow {
    std::uint64_t step = 0;
    double time = 0, front = 0, kinetic = 0;
    double dt = 0;                                // the step that led here (0 at step 0)
    double settlement = NAN;                      // the column: the top particle layer's mean downward displacement
    double stepping_s = 0;                        // seconds of mpm::advance (steps and reorderings) up to here
    double potential = 0, internal = 0;           // mpm::energy's other parts
    Locality order;                               // how far the particles' order has decayed
    ReorderCause reordered = ReorderCause::none;  // the reordering after this step, if one was due
};

struct Check {
    std::string name;
    bool passed = true;
    std::string detail;
};

struct Outcome {
    std::vector<FrontRow> rows;                 // step 0, then each step done
    std::vector<SnapshotEntry> snapshots;       // written, in order
    std::vector<std::uint64_t> snapshot_steps;  // the step of each snapshot
    std::uint64_t steps_done = 0;
    double wall_s = 0;      // the whole loop: steps, checks, snapshots, progress
    double stepping_s = 0;  // advance() alone: what particle-steps/s divide by
    // NaN (null in mpm.json) where not measured: the checks at the end run only after steps
    // whose checks passed.
    double mass_initial = NAN, mass_final = NAN;  // Σ mass over particles in id order
    double nodal_mass = NAN, nodal_error = NAN;   // Σ m_n of the final P2G; |Σ m_n - Σ m_p| / Σ m_p
    // The column (SimulationSettings::column): the analytical settlement of the top layer,
    // ρ g (H z0 - z0²/2) / M averaged over its particles' starting heights z0; the measured one
    // (the mean over the last tenth of the steps when damped, over all of them when not: the
    // mean of the undamped oscillation); and, damped, the RMS of σzz - (-ρ g (H - z0)) over all
    // particles at the end, relative to ρ g H.
    double settlement_exact = NAN, settlement_measured = NAN, settlement_error = NAN, stress_rms = NAN;
    // Damped or static: the same RMS of each horizontal layer of elements' mean σzz against the
    // exact at its particles' mean starting height (the profile, without the variation inside an
    // element that linear elements cannot represent).
    double stress_profile = NAN;
    // The free fall (SimulationSettings::free_fall): the worst distance from the exact fall, the mean fall's distance
    // from g t^2 / 2 and the step's g t dt / 2 at the last step before a wall acted, m; the steps before it.
    double fall_worst = NAN, fall_analytic = NAN, fall_bound = NAN;
    std::uint64_t fall_steps = 0;
    std::vector<Check> checks;  // "finite and inside the box", "energy bound", ("Newton": implicit and static), ("total
                                // energy": a fluid and implicit; "Ritter front": a fluid), "mass", "nodal mass"
    std::string failure;        // the first failed check, as one line; "" when all passed
    bool solver_failed = false;  // an implicit step's Newton or linear solve failed (its check says why)
    int signal = 0;              // the stop flag's value that ended the run early, else 0
    bool passed() const { return failure.empty(); }
};

// Runs `run.steps` steps of `st` under `setup` (mpm::advance), with a snapshot at step 0, every
// vtk_every steps and after the last step (or the step an interrupted run stopped at).
Outcome simulate(State& st, const Setup& setup, const SimulationSettings& run, const SimulationHooks& hooks);

// The snapshot file of step `step`: particles_000040.vtu.
std::string snapshot_name(std::uint64_t step);

// How many snapshots a run of `steps` writes: step 0, every `every`, and the last.
std::uint64_t snapshot_count(std::uint64_t steps, std::uint64_t every);

}  // namespace suite::mpm
