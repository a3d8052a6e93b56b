#pragma once
// What the MPM kernels check about their points (validate), their results (verify) and report
// (facts, footprint); apart from the kernels so that mpm_kernels.cpp stays the measured loops.
#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

#include "harness/kernel/kernel.hpp"
#include "kernels/mpm/mpm.hpp"

namespace suite::mpm {

// The box grid of about `elements` tetrahedra (6 a cube): a point's grid when --mesh is not given.
std::string box_spec_for(std::uint64_t elements);
// The tetrahedra of a --mesh spec; UsageError for a grid that is not tetrahedral.
std::uint64_t mesh_elements(const std::string& spec);

// What every MPM kernel's entry shares: group, formula, unit, the grid orderings, the variants
// (the scatter strategies with `strategies`, else the particle orders), the parameters ppe, case
// and warm-steps (and sort-every with `sorted_steps`), counted sizes, the grid's element count,
// the test size. The caller adds its bytes, notes, default meshes, make and validate.
KernelEntry mpm_entry(const std::string& name, const std::string& formula, const std::string& unit, bool strategies,
                      bool sorted_steps);

// A point's --sort-every: sort_auto for "auto", else its whole number of steps.
int sort_every_of(const KernelConfig& cfg);
// The steps of one repetition of a stepping kernel: K = --sort-every, or under auto `auto_steps`
// (a fixed number, so that every repetition does the same work whenever its reorderings fall).
inline int steps_per_repetition(int sort_every, int auto_steps) {
    return sort_every == sort_auto ? auto_steps : std::max(sort_every, 1);
}
// The facts of the reorderings after a stepping kernel's timing started (`since`: the tracker's
// count then): how many and by what cause, and under auto the threshold.
std::vector<Fact> reordering_facts(const State& st, const Setup& s, std::uint64_t since);
// The steps after which they happened and why, for a verification's detail: "; reordered after
// steps 12 (decayed), 40 (decayed), ..." (the first ten, and the count of the rest); "" for an
// order that never reorders.
std::string reorderings_text(const State& st, const Setup& s, std::uint64_t since);

// Throws UsageError for a grid spec that is not tetrahedral, --ppe that is not a whole number
// >= 1, --sort-every that is neither auto nor one, the serial strategy on more than one thread, or more memory than
// there is.
void validate_mpm(const KernelConfig& cfg, const std::string& kernel, const std::string& spec);

// The steps check_equivalence runs: the point's setup (a fixed K reordering every 2 steps, auto
// as the point has it: its trigger reads no clock) and the
// reference (natural grid, seeded particles, serial scatters), each from the start.
constexpr int equivalence_steps = 5;
// "" when every particle's position agrees to 1e-10 (the box is 1 long), else the worst one.
std::string check_equivalence(const Setup& point);

// "" when a serial P2G of the state's particles gives the nodes the state's strategy gave
// (1e-12 of each quantity's largest magnitude) and Σ m_n = Σ m_p (1e-12 relative).
std::string check_p2g_against_serial(State& st);

// "" when `calls` g2p calls from `start` give exactly the velocities and positions of `now`.
std::string check_g2p_replay(const State& start, const State& now, long calls);

// "" when every particle is finite, inside the box and located (w >= 0, Σ w = 1), the mass
// (summed in id order) equals `mass`, and a fresh P2G's nodal masses sum to it (1e-12).
std::string check_state(State& st, double mass);

// Neumaier's compensated sum: the mass sums compared here have 1e5 to 1e7 terms, whose plain
// sums drift apart by more than the 1e-12 the checks allow.
double compensated_sum(const std::vector<double>& v);

// Σ m_p in the order of the particles' ids (the same sum whatever order they are stored in).
double mass_by_id(const Particles& p);

// Node updates of a P2G whose node another thread's block of particles also updates (what the
// atomic strategy synchronises for nothing when that count is 0).
std::uint64_t atomic_conflicts(const State& st);

std::uint64_t footprint(const State& st);

// Each particle's mass indexed by its id, after checking that the ids are a permutation of
// 0..n-1; `why` says what is wrong when they are not (and the result is empty).
std::vector<double> masses_by_id(const Particles& p, std::string& why);

}  // namespace suite::mpm
