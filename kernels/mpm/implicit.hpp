#pragma once
// Implicit MPM: Newmark time integration of the active nodes' displacement increment Δu, solved
// by Newton's method with the consistent tangent, on the background grid of mpm.hpp (the
// equations in docs/mpm.md, "Implicit MPM"). One step:
//   project   m_n = Σ w m_p,  v_n = Σ w m_p v_p / m_n,  a_n = Σ w m_p a_p / m_n (the scatters of
//             mpm.hpp, under the state's strategy); the load m_n g; normal components on the walls 0
//   system    the active nodes (corners of elements holding particles) and the tangent's
//             pattern, rebuilt when the active elements change
//   Newton    from Δu = 0 (the undeformed grid, where the tangent is the material's own):
//               a' = (Δu - dt v_n - dt² (1/2 - β) a_n) / (β dt²)
//               r  = m_n g - f_int(Δu) - m_n a'          (static: r = m_n g - f_int(Δu))
//               K  = ∂f_int/∂Δu + m_n / (β dt²) I        (static: without the mass term)
//               solve K δ = r; Δu += δ (halved while that makes ||r|| larger, at most 8 times);
//               until ||r|| <= tol max(||r_0||, ||m_n g||) (g's load on the free rows)
//               or ||δ|| <= tol ||Δu||
//             f_int,i = Σ_p V_p P_p ∇N_i, with the step's deformation f = I + Σ_i Δu_i ⊗ ∇N_i:
//               large strain: E = (fᵀf - I)/2, S = σ_p + λ tr(E) I + 2μ E, P = f S
//               small strain: E = sym(f - I), P = σ_p + λ tr(E) I + 2μ E
//             (V_p scaled as mixed integration scales it, mpm.hpp)
//   update    x_p += Σ w Δu_n;  v_p += Σ w (v'_n - v_n);  a_p = Σ w a'_n, with
//             v'_n = v_n + dt ((1 - γ) a_n + γ a'_n) (static: v_p = a_p = 0);
//             σ_p = f S fᵀ / det f (large) or P (small);  V_p *= det f (large) or 1 + tr E (small)
// The grid returns to its original configuration, as in the explicit step. Nothing here prints
// or reads a clock.
#include <cstdint>
#include <string>

#include "kernels/mpm/mpm.hpp"

namespace suite::mpm {

// The step `suite mpm --integrator=implicit` takes without --dt: this many times the explicit
// stable step (implicit steps are not bound by the wave speed; 10x is where the tests check).
inline constexpr double implicit_default_multiple = 10;

// Throws UsageError for a fluid material (the implicit integrators have the elastic one only),
// Newmark parameters outside 1/2 <= γ <= 2β <= 1, or tolerances and limits that are not positive.
void check_implicit(const Settings& s);

// The phases of an implicit step, for the kernels that time one of them; implicit_step runs them.
// project: the nodal mass, velocity and acceleration and the load, the active system and its
// pattern, Δu = 0.
void implicit_project(State& st);
// f_int at the current Δu, into system.fint, and (with `tangent`) the tangent ∂f_int/∂Δu into
// system.val, without the mass term, under the state's scatter strategy (serial, atomic,
// colour, partition: implicit_assembly.cpp).
void implicit_assemble(State& st, bool tangent);
// The residual at the current Δu from system.fint (0 in the fixed rows); its norm.
double implicit_residual(State& st);
// Adds the mass term to the tangent's diagonal and makes the fixed rows and columns the identity.
void implicit_finish_tangent(State& st);
// Solves tangent δ = r into system.delta by the settings' solver. The iterations it took (0 for
// CHOLMOD), or -1 with `why` set when it failed (no convergence, not positive definite).
long implicit_solve(State& st, std::string& why);
// Jacobi-preconditioned CG on raw arrays (the system's own, or a kernel's placed copies): A x = b
// from x = 0 until ||b - A x|| <= tol ||b|| (the recursive residual). r, z, p, q and diag are
// scratch of n. Every loop is a `parallel for schedule(static)` over rows, the split a placed
// copy is first touched with. Returns as implicit_solve does.
struct CgArrays {
    std::int64_t n = 0;
    const std::uint32_t* row_ptr = nullptr;
    const std::uint32_t* col = nullptr;
    const double* val = nullptr;
    const double* b = nullptr;
    double* x = nullptr;
    double *r = nullptr, *z = nullptr, *p = nullptr, *q = nullptr, *diag = nullptr;
};
long jacobi_cg(const CgArrays& a, double tol, int max_iterations, std::string& why);
// Moves the particles by the converged Δu, updates their velocities, accelerations, stress and
// volume, and locates them.
void implicit_update(State& st);

// One whole implicit step. On a failure (st.implicit.failure, counted in failed_steps) the
// particles and the counts are left as they were and the state's time does not advance.
void implicit_step(State& st);

}  // namespace suite::mpm
