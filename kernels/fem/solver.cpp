#include "kernels/fem/solver.hpp"

#include <omp.h>

#include <algorithm>
#include <array>
#include <cmath>

#include "kernels/fem/inverse_iteration.hpp"

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

namespace {

// One thread of the team, as inverse_iteration_with sees it: its block of rows, the team's sums,
// and a barrier wherever another thread reads what this one wrote.
struct ThreadOfTeam {
    const Operator& a;
    const Operator& m;
    const EigenVectors& v;
    TeamSum& total;
    Block rows;

    template <class F>
    void each(F f) {
        f(rows.lo, rows.hi);
#pragma omp barrier
    }
    template <std::size_t K, class F>
    std::array<double, K> sum(F f) {
        std::array<double, K> s = f(rows.lo, rows.hi);
        for (double& x : s) x = total(x);
        return s;
    }
    void products() {
        a.apply(v.u, v.au, rows);
        m.apply(v.u, v.mu, rows);
    }
    void mass() {
        m.apply(v.u, v.f, rows);
#pragma omp barrier
    }
    CgResult solve(double tol, int max_iterations) {
        return cg_team(a, v.f, v.u, v.cg, tol, max_iterations, total, rows);
    }
};

}  // namespace

EigenResult inverse_iteration_team(const Operator& a, const Operator& m, const EigenVectors& v, double tol,
                                   double cg_tol, int max_cg, TeamSum& sum, Block rows) {
    ThreadOfTeam team{a, m, v, sum, rows};
    const EigenResult out = inverse_iteration_with(team, v, tol, cg_tol, max_cg);
#pragma omp barrier
    return out;
}

}  // namespace suite::fem
