#include "kernels/fem/fem_checks.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <mutex>
#include <utility>
#include <vector>

#include "harness/common/units.hpp"
#include "kernels/fem/element.hpp"
#include "kernels/mesh/edges.hpp"

namespace suite::fem {

namespace {

double row_scale(const Pattern& p, const double* v, std::int64_t i) {
    double s = 0;
    for (std::uint32_t k = p.row_ptr[i]; k < p.row_ptr[i + 1]; ++k) s = std::max(s, std::fabs(v[k]));
    return s;
}

std::string entry(const char* name, std::int64_t i, std::uint32_t j) {
    return std::string(name) + "(" + std::to_string(i) + ", " + std::to_string(j) + ")";
}

}  // namespace

std::string check_pattern(const MeshArrays& m, const Pattern& p) {
    for (std::int64_t i = 0; i < p.n; ++i) {
        bool diagonal = false;
        for (std::uint32_t k = p.row_ptr[i]; k < p.row_ptr[i + 1]; ++k) {
            if (k > p.row_ptr[i] && p.col[k] <= p.col[k - 1])
                return "row " + std::to_string(i) + " is not strictly ascending";
            if (p.col[k] >= p.n)
                return "row " + std::to_string(i) + " has column " + std::to_string(p.col[k]) + " out of range";
            if (p.col[k] == i) diagonal = true;
            if (find_entry(p, p.col[k], static_cast<std::uint32_t>(i)) < 0)
                return "the pattern is not symmetric at " + entry("", i, p.col[k]);
        }
        if (!diagonal) return "row " + std::to_string(i) + " has no diagonal entry";
    }
    for (std::int64_t e = 0; e < m.ne; ++e)
        for (int a = 0; a < 3; ++a)
            for (int b = 0; b < 3; ++b)
                if (find_entry(p, m.conn[3 * e + a], m.conn[3 * e + b]) < 0)
                    return "triangle " + std::to_string(e) + " has corners " + std::to_string(m.conn[3 * e + a]) +
                           " and " + std::to_string(m.conn[3 * e + b]) + ", whose entry is missing";
    const mesh::MeshView view{2,     static_cast<std::size_t>(m.nv), static_cast<std::size_t>(m.ne), m.x, m.y, nullptr,
                              m.conn};
    const std::uint64_t expected = static_cast<std::uint64_t>(m.nv) + 2 * mesh::build_edges(view).count();
    if (p.nnz() != expected)
        return std::to_string(p.nnz()) + " nonzeros, where vertices + 2 x edges = " + std::to_string(expected);
    return "";
}

std::string check_against(const Matrices& got, AssembledCsr& ref, double rel) {
    const Pattern rp = ref.pattern();
    const Pattern& p = got.pattern;
    if (p.n != rp.n || p.nnz() != rp.nnz()) return "the pattern differs from the serial reference's";
    for (std::int64_t i = 0; i < p.n; ++i) {
        const double sa = row_scale(rp, ref.a.data(), i), sm = row_scale(rp, ref.m.data(), i);
        for (std::uint32_t k = p.row_ptr[i]; k < p.row_ptr[i + 1]; ++k) {
            if (p.row_ptr[i] != rp.row_ptr[i] || p.col[k] != rp.col[k])
                return "row " + std::to_string(i) + "'s columns differ from the serial reference's";
            if (!(std::fabs(got.a[k] - ref.a[k]) <= rel * sa))
                return entry("A", i, p.col[k]) + " = " + format_number(got.a[k]) + ", serial " +
                       format_number(ref.a[k]);
            if (!(std::fabs(got.m[k] - ref.m[k]) <= rel * sm))
                return entry("M", i, p.col[k]) + " = " + format_number(got.m[k]) + ", serial " +
                       format_number(ref.m[k]);
        }
    }
    return "";
}

std::string check_properties(const MeshArrays& m, const Matrices& got, double delta, double rel) {
    const Pattern& p = got.pattern;
    for (std::int64_t i = 0; i < p.n; ++i) {
        const double sa = row_scale(p, got.a, i), sm = row_scale(p, got.m, i);
        for (std::uint32_t k = p.row_ptr[i]; k < p.row_ptr[i + 1]; ++k) {
            const std::int64_t t = find_entry(p, p.col[k], static_cast<std::uint32_t>(i));
            if (!(std::fabs(got.a[k] - got.a[t]) <= rel * sa))
                return entry("A", i, p.col[k]) + " != " + entry("A", p.col[k], static_cast<std::uint32_t>(i));
            if (!(std::fabs(got.m[k] - got.m[t]) <= rel * sm))
                return entry("M", i, p.col[k]) + " != " + entry("M", p.col[k], static_cast<std::uint32_t>(i));
        }
    }
    // The area from the coordinates, and ∫ k² φ_i by the same Gauss rule but its own loop.
    double area = 0;
    std::vector<double> load(static_cast<std::size_t>(m.nv), 0.0);
    for (std::int64_t e = 0; e < m.ne; ++e) {
        const std::uint32_t* c = m.conn + 3 * e;
        const double ex[3] = {m.x[c[0]], m.x[c[1]], m.x[c[2]]}, ey[3] = {m.y[c[0]], m.y[c[1]], m.y[c[2]]};
        const double t = 0.5 * std::fabs((ex[1] - ex[0]) * (ey[2] - ey[0]) - (ex[2] - ex[0]) * (ey[1] - ey[0]));
        area += t;
        for (int q = 0; q < 3; ++q) {
            double px = 0, py = 0;
            for (int j = 0; j < 3; ++j) {
                const double w = j == q ? gauss_major : gauss_minor;
                px += w * ex[j];
                py += w * ey[j];
            }
            const double k2 = k_squared(px, py, delta) * t / 3.0;
            for (int j = 0; j < 3; ++j) load[c[j]] += k2 * (j == q ? gauss_major : gauss_minor);
        }
    }
    double total_m = 0;
    for (std::uint64_t k = 0; k < p.nnz(); ++k) total_m += got.m[k];
    if (!(std::fabs(total_m - area) <= 1e-12 * area * std::sqrt(static_cast<double>(m.ne))))
        return "the entries of M add up to " + format_number(total_m) + ", the mesh's area is " + format_number(area);
    for (std::int64_t i = 0; i < p.n; ++i) {
        double row = 0, scale = 0;
        for (std::uint32_t k = p.row_ptr[i]; k < p.row_ptr[i + 1]; ++k) row += got.a[k], scale += std::fabs(got.a[k]);
        if (!(std::fabs(row + load[static_cast<std::size_t>(i)]) <=
              1e-10 * (scale + std::fabs(load[static_cast<std::size_t>(i)]))))
            return "row " + std::to_string(i) + " of A sums to " + format_number(row) +
                   ", -∫k²φ = " + format_number(-load[static_cast<std::size_t>(i)]);
    }
    return "";
}

void check_solve_outcome(const SolveOutcome& o, bool& solver_failed,
                         const std::function<void(const std::string&)>& fail) {
    const bool converged = o.cg ? o.cg_result.converged : o.eigen.converged && !o.eigen.cg_failed;
    if (!o.ran) {
        fail("no solve ran after setup");
    } else if (!converged) {
        solver_failed = true;
        if (o.cg || o.eigen.cg_failed)
            fail("conjugate gradients did not reach --cg-tol=" + format_number(o.cg_tol) +
                 " within --cg-max=" + std::to_string(o.max_cg) + " iterations");
        else
            fail("the inverse iteration did not reach --tol=" + format_number(o.tol) + " within " +
                 std::to_string(max_outer_iterations) + " steps");
    }
    // Converged, by the run's own tolerances: every solve's recursive residual within --cg-tol, and
    // the inverse iteration's last step within --tol (the CG solutions themselves: check_cg_solution).
    if (o.ran && converged && !o.cg) {
        if (!(o.eigen.worst_cg <= o.cg_tol))
            fail("a CG solve stopped at a recursive residual of " + format_number(o.eigen.worst_cg) +
                 ", above --cg-tol=" + format_number(o.cg_tol));
        if (!(o.eigen.last_change <= o.tol))
            fail("the inverse iteration stopped when λ moved by " + format_number(o.eigen.last_change) +
                 " (relative), above --tol=" + format_number(o.tol));
    }
    if (o.ran && o.cg_iterations() != o.setup_cg_iterations)
        fail(std::to_string(o.cg_iterations()) + " CG iterations, where the same solve took " +
             std::to_string(o.setup_cg_iterations) + " in setup");
}

double cg_rounding_margin(long iterations, std::int64_t longest_row, double abs_ax_norm, double f_norm) {
    const double u = std::ldexp(1.0, -53);
    return f_norm > 0 ? 2 * u * static_cast<double>(iterations + longest_row + 2) * abs_ax_norm / f_norm : 0;
}

std::string check_cg_solution(const Pattern& p, const double* a, const double* f, const double* x,
                              const CgResult& result, double tol, std::string& detail) {
    double rr = 0, ff = 0, aa = 0;
    std::int64_t longest = 0;
    for (std::int64_t i = 0; i < p.n; ++i) {
        double ax = 0, abs_ax = 0;
        for (std::uint32_t k = p.row_ptr[i]; k < p.row_ptr[i + 1]; ++k) {
            ax += a[k] * x[p.col[k]];
            abs_ax += std::fabs(a[k] * x[p.col[k]]);
        }
        longest = std::max<std::int64_t>(longest, p.row_ptr[i + 1] - p.row_ptr[i]);
        rr += (f[i] - ax) * (f[i] - ax);
        ff += f[i] * f[i];
        aa += abs_ax * abs_ax;
    }
    const double rel = std::sqrt(rr / ff),
                 margin = cg_rounding_margin(result.iterations, longest, std::sqrt(aa), std::sqrt(ff));
    detail = "||f - A x|| / ||f|| = " + format_number(rel) + " recomputed, within --cg-tol=" + format_number(tol) +
             " + " + format_number(margin) + " (rounding), the recursive " + format_number(result.relative_residual) +
             " within --cg-tol";
    return judge_cg_residuals(rel, result.relative_residual, tol, margin);
}

std::string judge_cg_residuals(double rel, double recursive, double tol, double margin) {
    if (!(recursive <= tol))
        return "CG stopped at a recursive residual of " + format_number(recursive) +
               ", above --cg-tol=" + format_number(tol);
    if (!(rel <= tol + margin))
        return "the recomputed ||f - A x|| / ||f|| = " + format_number(rel) + ", above --cg-tol=" + format_number(tol) +
               " + " + format_number(margin) + " (rounding)";
    return "";
}

std::string check_same_lambda(const std::string& key, const std::string& who, double lambda) {
    static std::mutex lock;
    static std::map<std::string, std::pair<double, std::string>> first;
    const std::lock_guard<std::mutex> hold(lock);
    const auto [it, inserted] = first.emplace(key, std::make_pair(lambda, who));
    if (inserted) return "";
    const double rel = std::fabs(lambda - it->second.first) / std::fabs(it->second.first);
    if (rel <= 1e-7) return "";
    return "λ = " + format_number(lambda) + " differs from the " + it->second.second + " point's " +
           format_number(it->second.first) + " by " + format_number(rel) + " (relative), more than 1e-7";
}

std::string check_symmetric_product(const Pattern& p, const double* a, const SymmetricPattern& s, SymmetricValues v,
                                    const double* x, const double* y, std::string& detail) {
    const std::int64_t n = p.n;
    std::vector<double> replay(static_cast<std::size_t>(n));
    symmetric_product_replay(s, v, x, replay.data());
    std::string wrong;
    double worst = 0;
    for (std::int64_t i = 0; i < n; ++i) {
        double full = 0, scale = 0;
        for (std::uint32_t k = p.row_ptr[i]; k < p.row_ptr[i + 1]; ++k) {
            full += a[k] * x[p.col[k]];
            scale += std::fabs(a[k] * x[p.col[k]]);
        }
        const double rel = scale > 0 ? std::fabs(y[i] - full) / scale : std::fabs(y[i] - full);
        worst = std::max(worst, rel);
        if (!wrong.empty()) continue;
        if (replay[static_cast<std::size_t>(i)] != y[i])
            wrong = "y[" + std::to_string(i) + "] = " + format_number(y[i]) +
                    ", a serial replay of the same schedule " + format_number(replay[static_cast<std::size_t>(i)]) +
                    " (a race between threads?)";
        else if (!(rel <= 1e-12))
            wrong = "y[" + std::to_string(i) + "] = " + format_number(y[i]) + ", the full CSR product " +
                    format_number(full) + " (" + format_number(rel) + " of the row's Σ|a x|, above 1e-12)";
    }
    detail = "the symmetric y = A x equals a serial replay of its schedule exactly and the full CSR product to " +
             format_number(worst) + " of the row's Σ|a x| (1e-12 allowed)";
    return wrong;
}

}  // namespace suite::fem
