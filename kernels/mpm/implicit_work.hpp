#pragma once
// What one repetition of the implicit MPM kernels moves and computes, counted from their loops
// (implicit_kernels.cpp reports it; the runner derives every rate from it). Bytes follow the
// STREAM convention: the particle arrays a pass reads and writes, the tangent's values written
// once, the CG's matrix and vectors each pass; a multiply-add counts as two flops.
#include "harness/kernel/kernel.hpp"

namespace suite::mpm {

// Per particle: elem, V, σ read (the tangent's values are counted by the matrix).
constexpr double assembly_particle_bytes = 4 + 8 + 48;
// The large-strain loop of implicit_assembly.cpp, counted (a multiply-add as two): F 72, E 63,
// S 38, P 45, the forces 72, G and F Fᵀ 105; per corner pair ∇N_i·∇N_j 6, ∇N_i·S∇N_j 27 and the
// nine entries 90.
constexpr double assembly_flops = 395 + 16 * 123;
// A step's passes over the particle arrays besides the assemblies: the projection (w, elem, m,
// v, a), the update (elem, w, σ, V, x, v, a read; σ, V, x, v, a written), locate (x, elem read;
// w, elem written).
constexpr double step_particle_bytes =
    (32 + 4 + 8 + 24 + 24) + (4 + 32 + 48 + 8 + 24 + 24 + 24) + (48 + 8 + 24 + 24 + 24) + (24 + 4 + 32 + 4);
// One CG iteration: the product (values, columns, p gathered, q written) and the vector updates
// (x, r, z, p read and written, q and the diagonal read).
inline double cg_bytes(double nnz, double rows) { return 12 * nnz + rows * 8 * (2 + 8 + 2); }
inline double cg_flops(double nnz, double rows) { return 2 * nnz + 12 * rows; }

// One assembly of f_int and the tangent: its particles, and the matrix's values written.
inline Work assembly_work(double particles, double nnz, double rows) {
    Work w;
    w.units = particles;
    w.stream_bytes = particles * assembly_particle_bytes + 8 * (nnz + rows);
    w.flops = particles * assembly_flops;
    return w;
}

// One Newton system solved by `iterations` CG iterations; a unit is an iteration.
inline Work solve_work(double iterations, double nnz, double rows) {
    Work w;
    w.units = iterations;
    w.stream_bytes = iterations * cg_bytes(nnz, rows);
    w.flops = iterations * cg_flops(nnz, rows);
    return w;
}

// `steps` whole implicit steps of `newton` Newton iterations (an assembly each, one more to
// confirm) and `cg` CG iterations each; a unit is a particle-step.
inline Work step_work(double steps, double particles, double newton, double cg, double nnz, double rows) {
    Work w;
    w.units = particles * steps;
    w.stream_bytes = steps * (particles * (step_particle_bytes + (newton + 1) * assembly_particle_bytes) +
                              (newton + 1) * 8 * (nnz + rows) + cg * cg_bytes(nnz, rows));
    w.flops = steps * (particles * (newton + 1) * assembly_flops + cg * cg_flops(nnz, rows));
    return w;
}

}  // namespace suite::mpm
