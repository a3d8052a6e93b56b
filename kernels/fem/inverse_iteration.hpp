#pragma once
// The inverse power iteration (the thesis's Algorithm 3), written once for the two ways it runs:
// by every thread of an OpenMP team inside one parallel region (solver.cpp), and by every rank of
// a distributed run with halo exchanges (distributed.cpp). The algorithm:
//   u = 1; repeat  f = M u,  solve A u' = f by CG from u / λ,  u = u' scaled to u'ᵀ M u' = 1 with
//   Σ u > 0,  λ = uᵀ A u / uᵀ M u,  until |λ - λ_old| <= tol |λ_old|
// then the residual ||A u - λ M u|| / ||λ M u||. The Team says how each step is done:
//   each(f)           f(lo, hi) on the caller's rows; every row done before anyone reads it again
//   sum<K>(f)         f(lo, hi) -> std::array<double, K> partial sums; returns the totals, the same
//                     for every caller (summed in a fixed order, so a run repeats its bits)
//   products()        v.au = A u and v.mu = M u on the caller's rows (reads u whole)
//   mass()            v.f = M u on the caller's rows, before anyone writes u again
//   solve(tol, max)   A u = v.f by CG from the u given: its CgResult
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

#include "kernels/fem/solver.hpp"

namespace suite::fem {

template <class Team>
EigenResult inverse_iteration_with(Team& team, const EigenVectors& v, double tol, double cg_tol, int max_cg) {
    double* const u = v.u;
    EigenResult out;
    // The Rayleigh quotient of u, and u scaled to uᵀMu = 1 with Σu > 0 (the eigenvector's sign).
    auto rayleigh_and_normalise = [&] {
        team.products();
        const auto [uau, umu, su] = team.template sum<3>([&](std::int64_t lo, std::int64_t hi) {
            double uau = 0, umu = 0, su = 0;
            for (std::int64_t i = lo; i < hi; ++i) {
                uau += u[i] * v.au[i];
                umu += u[i] * v.mu[i];
                su += u[i];
            }
            return std::array<double, 3>{uau, umu, su};
        });
        const double scale = (su < 0 ? -1.0 : 1.0) / std::sqrt(umu);
        team.each([&](std::int64_t lo, std::int64_t hi) {
            for (std::int64_t i = lo; i < hi; ++i) u[i] *= scale;
        });
        return uau / umu;
    };
    team.each([&](std::int64_t lo, std::int64_t hi) {
        for (std::int64_t i = lo; i < hi; ++i) u[i] = 1.0;
    });
    double lambda = rayleigh_and_normalise();
    while (out.iterations < max_outer_iterations) {
        ++out.iterations;
        team.mass();
        // The solution is near u / λ once u has converged: start there.
        team.each([&](std::int64_t lo, std::int64_t hi) {
            for (std::int64_t i = lo; i < hi; ++i) u[i] /= lambda;
        });
        const CgResult cg = team.solve(cg_tol, max_cg);
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
    team.products();
    const auto [res, ref] = team.template sum<2>([&](std::int64_t lo, std::int64_t hi) {
        double res = 0, ref = 0;
        for (std::int64_t i = lo; i < hi; ++i) {
            const double d = v.au[i] - lambda * v.mu[i];
            res += d * d;
            ref += lambda * lambda * v.mu[i] * v.mu[i];
        }
        return std::array<double, 2>{res, ref};
    });
    out.residual = ref > 0 ? std::sqrt(res / ref) : 0;
    return out;
}

}  // namespace suite::fem
