#pragma once
// `suite mpm`'s run once every option is checked and the state built: the steps, with the checks
// after each (every particle's position and velocity finite, every particle inside the box, the
// kinetic energy within what gravity can release: an unstable step shows there first), the
// progress line, the particle snapshots, and the checks at the end (each particle's mass what it
// was at the start, bit for bit; a P2G of the final particles puts on the nodes the particles'
// total mass to 1e-12). mpm.cpp parses, checks and wires; mpm_report.cpp renders the outcome.
#include <atomic>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "harness/common/output_file.hpp"
#include "kernels/mpm/mpm.hpp"
#include "kernels/mpm/vtk.hpp"

namespace suite {

struct MpmRunSettings {
    std::uint64_t steps = 1000;
    std::uint64_t vtk_every = 50;  // 0: no snapshots
    bool quiet = false;            // no progress line
};

// One row of front.csv: after `step` steps.
struct MpmFrontRow {
    std::uint64_t step = 0;
    double time = 0, front = 0, kinetic = 0;
};

struct MpmCheck {
    std::string name;
    bool passed = true;
    std::string detail;
};

struct MpmOutcome {
    std::vector<MpmFrontRow> rows;               // step 0, then each step done
    std::vector<mpm::SnapshotEntry> snapshots;   // written, in order
    std::vector<std::uint64_t> snapshot_steps;   // the step of each snapshot
    std::uint64_t steps_done = 0;
    double wall_s = 0;       // the whole loop: steps, checks, snapshots, progress
    double stepping_s = 0;   // advance() alone: what particle-steps/s divide by
    // NaN (null in mpm.json) where not measured: the checks at the end run only after steps
    // whose checks passed.
    double mass_initial = NAN, mass_final = NAN;  // Σ mass over particles in id order
    double nodal_mass = NAN, nodal_error = NAN;   // Σ m_n of the final P2G; |Σ m_n - Σ m_p| / Σ m_p
    std::vector<MpmCheck> checks;                // "finite and inside the box", "energy bound", "mass", "nodal mass"
    std::string failure;     // the first failed check, as one line; "" when all passed
    int signal = 0;          // SIGINT/SIGTERM that stopped the run, else 0
    bool passed() const { return failure.empty(); }
};

// Runs `settings.steps` steps of `st` under `setup` (mpm::advance), writing into `out` the
// snapshot particles_SSSSSS.vtu at step 0, every vtk_every steps and after the last step.
// Stops at the first failed check (after a NaN there is nothing left to simulate) or at
// SIGINT/SIGTERM; either way the outcome holds what was done.
MpmOutcome mpm_simulate(mpm::State& st, const mpm::Setup& setup, const MpmRunSettings& settings, const OutputDir& out);

// The snapshot file of step `step`: particles_000040.vtu.
std::string mpm_snapshot_name(std::uint64_t step);

}  // namespace suite
