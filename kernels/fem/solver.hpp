#pragma once
// Conjugate gradients and the inverse power iteration (the thesis's Algorithm 3) on the CSR
// matrices, run by the whole OpenMP team inside one parallel region: each thread owns a block of
// rows (the split of first touch), and every reduction is summed in thread order by every thread,
// so that all threads take the same decisions and a result depends on the thread count only.
//   cg:      solve A x = f from the given x until ||f - A x|| <= tol ||f|| (the recursive residual)
//   inverse: u = 1; repeat f = M u, solve A u' = f by cg (from u / λ), u = u' / sqrt(u'ᵀ M u'),
//            λ = u'ᵀ A u' / u'ᵀ M u', until |λ - λ_old| <= tol |λ_old|
#include <cstdint>

#include "harness/kernel/blocks.hpp"
#include "kernels/fem/csr.hpp"
#include "kernels/fem/sell.hpp"
#include "kernels/fem/symmetric.hpp"

namespace suite::fem {

// The matrix a solver multiplies by: its CSR rows (--strategy=csr), the symmetric storage of
// symmetric.hpp (--strategy=symmetric, the team of its counts), or SELL-C-σ of sell.hpp
// (--strategy=sell, the team of its counts).
struct Operator {
    const Pattern* csr = nullptr;
    const double* values = nullptr;
    const SymmetricPattern* sym = nullptr;
    SymmetricValues sym_values;
    const SellPattern* sell = nullptr;
    const double* sell_values = nullptr;

    static Operator of_csr(const Pattern& p, const double* v) { return {&p, v, nullptr, {}, nullptr, nullptr}; }
    static Operator of_symmetric(const SymmetricPattern& s, SymmetricValues v) {
        return {nullptr, nullptr, &s, v, nullptr, nullptr};
    }
    static Operator of_sell(const SellPattern& s, const double* v) { return {nullptr, nullptr, nullptr, {}, &s, v}; }

    // y = A x by the whole team, `rows` this thread's block (my_block); x whole before. Calls
    // on_row(i, y_i) once for each row, by the thread that completes it. CSR and SELL: this
    // thread's rows (SELL: in row order a window at a time), no barrier; symmetric: ends with a
    // barrier (y whole after it).
    template <class OnRow>
    void apply(const double* x, double* y, Block rows, OnRow&& on_row) const {
        if (sym) {
            symmetric_product_team(*sym, sym_values, x, y, on_row);
            return;
        }
        if (sell) {
            sell_rows(*sell, sell_values, x, y, omp_get_thread_num(), rows, on_row);
            return;
        }
        const std::uint32_t* const rp = csr->row_ptr;
        const std::uint32_t* const col = csr->col;
        const double* const a = values;
        for (std::int64_t i = rows.lo; i < rows.hi; ++i) {
            double s = 0;
#pragma GCC unroll 4
            for (std::uint32_t k = rp[i], end = rp[i + 1]; k < end; ++k) s += a[k] * x[col[k]];
            y[i] = s;
            on_row(i, s);
        }
    }
    void apply(const double* x, double* y, Block rows) const {
        apply(x, y, rows, [](std::int64_t, double) {});
    }
};

// Sums one number from every thread of the team; every thread gets the total. Two slots of
// cache-line-padded partial sums, used in turn: a slot is written again only after the barrier
// of the sum in between, by which time every thread has read it.
class TeamSum {
public:
    explicit TeamSum(double* partial) : partial_(partial) {}  // 2 * 8 * threads doubles, shared
    double operator()(double mine);

private:
    double* partial_;
    int slot_ = 0;  // per thread: each thread owns its copy of the TeamSum
};

struct CgVectors {
    double* r = nullptr;
    double* p = nullptr;
    double* q = nullptr;
};

struct CgResult {
    int iterations = 0;
    bool converged = false;
    double relative_residual = 0;  // ||r|| / ||f||, recursive
};

// Called by every thread of the team; rows [rows.lo, rows.hi) are this thread's (blocks.hpp).
// x holds the starting guess and, on return, the solution. Ends with a barrier.
CgResult cg_team(const Pattern& p, const double* a, const double* f, double* x, const CgVectors& v, double tol,
                 int max_iterations, TeamSum& sum, Block rows);
CgResult cg_team(const Operator& a, const double* f, double* x, const CgVectors& v, double tol, int max_iterations,
                 TeamSum& sum, Block rows);

struct EigenVectors {
    double* u = nullptr;
    double* f = nullptr;
    double* au = nullptr;
    double* mu = nullptr;
    CgVectors cg;
};

struct EigenResult {
    double lambda = 0;
    int iterations = 0;      // of the outer loop
    long cg_iterations = 0;  // over all solves
    bool converged = false;  // outer loop within its limit
    bool cg_failed = false;  // a solve did not converge within max_cg
    double residual = 0;     // ||A u - λ M u|| / ||λ M u|| at the end
    double last_change = 0;  // |λ - λ_old| / |λ_old| of the last step: the stopping rule's figure
    double worst_cg = 0;     // the largest recursive ||r|| / ||f|| a solve stopped at
};

constexpr int max_outer_iterations = 1000;

// Called by every thread of the team. Ends with a barrier; every thread returns the same result.
EigenResult inverse_iteration_team(const Pattern& p, const double* a, const double* m, const EigenVectors& v,
                                   double tol, double cg_tol, int max_cg, TeamSum& sum, Block rows);
EigenResult inverse_iteration_team(const Operator& a, const Operator& m, const EigenVectors& v, double tol,
                                   double cg_tol, int max_cg, TeamSum& sum, Block rows);

}  // namespace suite::fem
