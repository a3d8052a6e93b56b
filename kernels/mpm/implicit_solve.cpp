// The linear solve of a Newton iteration (implicit.hpp): K δ = r on the active system.
//   cg       conjugate gradients preconditioned by K's diagonal (Jacobi), from δ = 0, until
//            ||r - K δ|| <= cg_tol ||r|| (the recursive residual); a direction with pᵀKp <= 0
//            means K is not positive definite
//   cholmod  CHOLMOD's supernodal LLᵀ in its own fill-reducing order, factorised anew (the
//            reference: a library's direct solve); also the fallback where CG runs out of
//            iterations (counted in ImplicitStats::fallbacks)
#include <cmath>
#include <exception>
#include <string>

#include "harness/common/units.hpp"
#include "kernels/fem/sparse_libs.hpp"
#include "kernels/mpm/implicit.hpp"

namespace suite::mpm {

namespace {

long solve_cg(ActiveSystem& sys, const ImplicitSettings& im, std::string& why) {
    const std::size_t n = sys.rows();
    for (auto* v : {&sys.cg_z, &sys.cg_p, &sys.cg_q, &sys.cg_diag, &sys.cg_r}) v->resize(n);
    const CgArrays a{static_cast<std::int64_t>(n),
                     sys.row_ptr.data(),
                     sys.col.data(),
                     sys.val.data(),
                     sys.r.data(),
                     sys.delta.data(),
                     sys.cg_r.data(),
                     sys.cg_z.data(),
                     sys.cg_p.data(),
                     sys.cg_q.data(),
                     sys.cg_diag.data()};
    return jacobi_cg(a, im.cg_tol, im.cg_max, why);
}

}  // namespace

long jacobi_cg(const CgArrays& a, double tol, int max_iterations, std::string& why) {
    const std::int64_t n = a.n;
    double* const x = a.x;
    double* const rr = a.r;
    double* const z = a.z;
    double* const p = a.p;
    double* const q = a.q;
    double* const d = a.diag;
    const double* const b = a.b;
    const std::uint32_t* const rp = a.row_ptr;
    const std::uint32_t* const col = a.col;
    const double* const val = a.val;
    double rz = 0, bb = 0;
#pragma omp parallel for schedule(static) reduction(+ : rz, bb)
    for (std::int64_t i = 0; i < n; ++i) {
        double diag = 0;
        for (std::uint32_t k = rp[i]; k < rp[i + 1]; ++k)
            if (col[k] == static_cast<std::uint32_t>(i)) diag = val[k];
        d[i] = diag > 0 ? 1 / diag : 1;
        x[i] = 0;
        rr[i] = b[i];
        z[i] = d[i] * rr[i];
        p[i] = z[i];
        rz += rr[i] * z[i];
        bb += rr[i] * rr[i];
    }
    const double goal = tol * tol * bb;
    if (bb == 0) return 0;
    for (long it = 1; it <= max_iterations; ++it) {
        double pq = 0;
#pragma omp parallel for schedule(static) reduction(+ : pq)
        for (std::int64_t i = 0; i < n; ++i) {
            double s = 0;
            for (std::uint32_t k = rp[i]; k < rp[i + 1]; ++k) s += val[k] * p[col[k]];
            q[i] = s;
            pq += p[i] * s;
        }
        if (!(pq > 0)) {
            why = "the tangent is not positive definite (CG met pᵀKp = " + format_number(pq) + " at iteration " +
                  std::to_string(it) + "): the system is singular or the step too large; give a smaller --dt";
            return -1;
        }
        const double alpha = rz / pq;
        double rnorm = 0, rz_new = 0;
#pragma omp parallel for schedule(static) reduction(+ : rnorm, rz_new)
        for (std::int64_t i = 0; i < n; ++i) {
            x[i] += alpha * p[i];
            rr[i] -= alpha * q[i];
            z[i] = d[i] * rr[i];
            rnorm += rr[i] * rr[i];
            rz_new += rr[i] * z[i];
        }
        if (rnorm <= goal) return it;
        const double beta = rz_new / rz;
        rz = rz_new;
#pragma omp parallel for schedule(static)
        for (std::int64_t i = 0; i < n; ++i) p[i] = z[i] + beta * p[i];
    }
    why = "CG did not converge in " + std::to_string(max_iterations) + " iterations (tolerance " + format_number(tol) +
          "); try --solver=cholmod or a smaller --dt";
    return -1;
}

namespace {

long solve_cholmod(ActiveSystem& sys, std::string& why) {
    const std::string missing = fem::sparse_libs_missing();
    if (!missing.empty()) {
        why = "--solver=cholmod: built without " + missing;
        return -1;
    }
    fem::Csr a;
    a.n = static_cast<std::int64_t>(sys.rows());
    a.row_ptr = sys.row_ptr;
    a.col = sys.col;
    a.val = sys.val;
    try {
        sys.delta = fem::cholesky_solve(a, sys.r);
    } catch (const fem::NotDefinite& e) {
        why = "the tangent is not positive definite (CHOLMOD met a non-positive pivot at column " +
              std::to_string(e.minor) + "): the system is singular or the step too large; give a smaller --dt";
        return -1;
    } catch (const std::exception& e) {
        why = std::string("CHOLMOD failed: ") + e.what();
        return -1;
    }
    return 0;
}

}  // namespace

long implicit_solve(State& st, std::string& why) {
    ActiveSystem& sys = st.system;
    sys.delta.assign(sys.rows(), 0);
    if (st.settings.implicit.solver == LinearSolver::cholmod) return solve_cholmod(sys, why);
    long its = solve_cg(sys, st.settings.implicit, why);
    // The fallback: CG that ran out of iterations (not one that met an indefinite K, which a
    // factorisation would meet too) hands the system to CHOLMOD, and the step goes on.
    if (its < 0 && why.rfind("CG did not converge", 0) == 0 && fem::sparse_libs_missing().empty()) {
        const std::string cg_why = why;
        why.clear();
        sys.delta.assign(sys.rows(), 0);
        if (solve_cholmod(sys, why) < 0) {
            why = cg_why + "; CHOLMOD, the fallback, failed too: " + why;
            return -1;
        }
        ++st.implicit.fallbacks;
        return st.settings.implicit.cg_max;
    }
    return its;
}

}  // namespace suite::mpm
