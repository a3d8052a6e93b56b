#pragma once
// The implicit integrator's settings and the linear system of a step (implicit.hpp has the
// method); apart from it so that mpm.hpp's Settings and State can hold them.
#include <cstdint>
#include <string>
#include <vector>

namespace suite::mpm {

// How a step advances in time:
//   explicit   the USL step of mpm.hpp, bound by the wave speed
//   implicit   Newmark on the active nodes' displacement increment, Newton on the residual
//   static     as implicit without the inertia: each step an equilibrium under the load
enum class Integrator { explicit_step, implicit, quasi_static };
Integrator parse_integrator(const std::string& name);  // throws UsageError (choices.hpp, integrators())
const char* integrator_name(Integrator i);

// The linear solve of a Newton iteration: the suite's own CG with a Jacobi preconditioner (what
// is measured), or CHOLMOD's sparse Cholesky factorisation (the reference and the fallback).
enum class LinearSolver { cg, cholmod };
LinearSolver parse_linear_solver(const std::string& name);  // throws UsageError (choices.hpp)
const char* linear_solver_name(LinearSolver s);

struct ImplicitSettings {
    // Newmark's β and γ; average acceleration (1/4, 1/2) conserves a linear problem's energy.
    // Accepted: 1/2 <= γ <= 2β <= 1 (unconditionally stable; implicit.cpp refuses the rest).
    double beta = 0.25, gamma = 0.5;
    // The step's Green-Lagrange strain and the geometric stiffness (true), or the small-strain
    // increment and the material stiffness alone (false: the residual is then linear in the
    // increment and Newton ends after one solve). docs/mpm.md, "Implicit MPM", says when which.
    bool large_strain = true;
    double residual_tol = 1e-8;  // Newton: converged when ||r_k|| <= residual_tol max(||r_0||, ||m_n g||) (free rows),
    double increment_tol = 1e-10;  // or when the last correction ||δ|| <= increment_tol ||Δu||
    int newton_max = 25;
    LinearSolver solver = LinearSolver::cg;
    double cg_tol = 1e-11;  // ||r - K δ|| <= cg_tol ||r||: below residual_tol, so that Newton can reach it
    int cg_max = 20000;
};

// The linear system of one step on the active nodes: the corners of the elements that hold
// particles, numbered in the grid's node order (so the grid's ordering and the dynamic
// renumbering order the system too). Three rows a node (x, y, z); the rows of a node share their
// columns, three a neighbouring node, ascending. The pattern is rebuilt when the set of active
// elements changes.
struct ActiveSystem {
    std::vector<std::uint32_t> elements;      // the active elements, ascending
    std::vector<std::uint32_t> node;          // active index -> grid node
    std::vector<std::int32_t> index;          // grid node -> active index, or -1
    std::vector<std::uint32_t> row_ptr, col;  // 3 rows per active node
    // 16 per grid element (meaningful for the active ones): entry 4 i + j is where corner j's
    // three columns start within each of corner i's rows (row_ptr[3 index(i) + a] + block + b).
    std::vector<std::uint32_t> block;
    std::vector<std::uint8_t> fixed;  // per row: the displacement normal to a wall, held at 0
    std::vector<double> val;          // the tangent
    std::vector<double> mass;         // per active node: m_n (lumped)
    // Per row: the nodal velocity and acceleration at the step's start, the load m_n g, the
    // internal force, the increment Δu, the residual, the Newton correction δ.
    std::vector<double> v, a, fext, fint, du, r, delta;
    std::vector<double> cg_r, cg_z, cg_p, cg_q, cg_diag;  // the solver's scratch
    std::uint64_t patterns = 0;                           // pattern builds so far
    std::size_t rows() const { return 3 * node.size(); }
};

// What the implicit steps did, for the checks and the record's facts.
struct ImplicitStats {
    std::uint64_t newton = 0;             // Newton iterations (linear solves) over all steps
    std::uint64_t solver_iterations = 0;  // CG iterations over all solves (0 with CHOLMOD)
    std::uint64_t backtracks = 0;         // corrections halved because they made the residual larger
    std::uint64_t fallbacks = 0;          // CG solves that ran out of iterations and were handed to CHOLMOD
    std::uint64_t failed_steps = 0;       // steps that failed (each left the state as it was)
    int last_newton = 0, max_newton = 0;
    std::vector<double> last_residuals;  // ||r_k|| / max(||r_0||, ||m g||) in the last step, k = 0, 1, ...
    double worst_residual = 0;           // the largest final one of any step
    std::uint64_t active_rows = 0;       // the last step's system
    std::uint64_t nonzeros = 0;
    // Why the last step failed ("" when it did not): Newton beyond newton_max, a solve that did
    // not converge, a singular system. The step leaves the particles as they were.
    std::string failure;
};

}  // namespace suite::mpm
