#include "kernels/fem/solver.hpp"

#include <omp.h>

#include <algorithm>
#include <cmath>

namespace suite::fem {

double TeamSum::operator()(double mine) {
    const int t = omp_get_thread_num(), nt = omp_get_num_threads();
    double* slot = partial_ + static_cast<std::ptrdiff_t>(slot_) * 8 * nt;
    slot_ ^= 1;
    slot[8 * t] = mine;
#pragma omp barrier
    double total = 0;
    for (int k = 0; k < nt; ++k) total += slot[8 * k];
    return total;
}

CgResult cg_team(const Pattern& pat, const double* a, const double* f, double* x, const CgVectors& v, double tol,
                 int max_iterations, TeamSum& sum, Block rows) {
    return cg_team(Operator::of_csr(pat, a), f, x, v, tol, max_iterations, sum, rows);
}

EigenResult inverse_iteration_team(const Pattern& pat, const double* a, const double* m, const EigenVectors& v,
                                   double tol, double cg_tol, int max_cg, TeamSum& sum, Block rows) {
    return inverse_iteration_team(Operator::of_csr(pat, a), Operator::of_csr(pat, m), v, tol, cg_tol, max_cg, sum,
                                  rows);
}

CgResult cg_team(const Operator& a, const double* f, double* x, const CgVectors& v, double tol, int max_iterations,
                 TeamSum& sum, Block rows) {
    double* const r = v.r;
    double* const p = v.p;
    double* const q = v.q;
    // r = f - A x, p = r.
    a.apply(x, q, rows);
    double rr = 0, ff = 0;
    for (std::int64_t i = rows.lo; i < rows.hi; ++i) {
        r[i] = f[i] - q[i];
        p[i] = r[i];
        rr += r[i] * r[i];
        ff += f[i] * f[i];
    }
    rr = sum(rr);
    ff = sum(ff);
    CgResult out;
    const double goal = tol * tol * ff;
    while (true) {
        if (rr <= goal) {
            out.converged = true;
            break;
        }
        if (out.iterations >= max_iterations) break;
        ++out.iterations;
        // q = A p and pᵀq in one pass; p is whole: the barrier ending the last iteration came after it.
        double pq = 0;
        a.apply(p, q, rows, [&](std::int64_t i, double qi) { pq += p[i] * qi; });
        pq = sum(pq);
        const double alpha = rr / pq;
        double rr_new = 0;
        for (std::int64_t i = rows.lo; i < rows.hi; ++i) {
            x[i] += alpha * p[i];
            r[i] -= alpha * q[i];
            rr_new += r[i] * r[i];
        }
        rr_new = sum(rr_new);
        const double beta = rr_new / rr;
        rr = rr_new;
        for (std::int64_t i = rows.lo; i < rows.hi; ++i) p[i] = r[i] + beta * p[i];
#pragma omp barrier
    }
    out.relative_residual = ff > 0 ? std::sqrt(rr / ff) : 0;
#pragma omp barrier
    return out;
}

EigenResult inverse_iteration_team(const Operator& a, const Operator& m, const EigenVectors& v, double tol,
                                   double cg_tol, int max_cg, TeamSum& sum, Block rows) {
    double* const u = v.u;
    EigenResult out;
    // The Rayleigh quotient of u, and u scaled to uᵀMu = 1 with Σu > 0 (the eigenvector's sign).
    auto rayleigh_and_normalise = [&] {
        a.apply(u, v.au, rows);
        m.apply(u, v.mu, rows);
        double uau = 0, umu = 0, su = 0;
        for (std::int64_t i = rows.lo; i < rows.hi; ++i) {
            uau += u[i] * v.au[i];
            umu += u[i] * v.mu[i];
            su += u[i];
        }
        uau = sum(uau);
        umu = sum(umu);
        su = sum(su);
        const double scale = (su < 0 ? -1.0 : 1.0) / std::sqrt(umu);
        for (std::int64_t i = rows.lo; i < rows.hi; ++i) u[i] *= scale;
        return uau / umu;
    };
    for (std::int64_t i = rows.lo; i < rows.hi; ++i) u[i] = 1.0;
#pragma omp barrier
    double lambda = rayleigh_and_normalise();
    while (out.iterations < max_outer_iterations) {
        ++out.iterations;
        // u is read whole by the SpMV: the barrier of the last sum came before the scaling, so wait.
#pragma omp barrier
        m.apply(u, v.f, rows);
#pragma omp barrier
        // The solution is near u / λ once u has converged: start there.
        for (std::int64_t i = rows.lo; i < rows.hi; ++i) u[i] /= lambda;
#pragma omp barrier
        const CgResult cg = cg_team(a, v.f, u, v.cg, cg_tol, max_cg, sum, rows);
        out.cg_iterations += cg.iterations;
        out.worst_cg = std::max(out.worst_cg, cg.relative_residual);
        if (!cg.converged) {
            out.cg_failed = true;
            break;
        }
        const double previous = lambda;
        lambda = rayleigh_and_normalise();
        out.last_change = std::fabs(lambda - previous) / std::fabs(previous);
        if (std::fabs(lambda - previous) <= tol * std::fabs(previous)) {
            out.converged = true;
            break;
        }
    }
    out.lambda = lambda;
    // The residual of the final u: A u and M u again, after its scaling.
#pragma omp barrier
    a.apply(u, v.au, rows);
    m.apply(u, v.mu, rows);
    double res = 0, ref = 0;
    for (std::int64_t i = rows.lo; i < rows.hi; ++i) {
        const double d = v.au[i] - lambda * v.mu[i];
        res += d * d;
        ref += lambda * lambda * v.mu[i] * v.mu[i];
    }
    res = sum(res);
    ref = sum(ref);
    out.residual = ref > 0 ? std::sqrt(res / ref) : 0;
#pragma omp barrier
    return out;
}

}  // namespace suite::fem
