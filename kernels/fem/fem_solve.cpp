// The solver kernels on the assembled P1 matrices (solver.hpp has the algorithms). One repetition:
//   fem-spmv    y = A x                                     rated in nonzeros/s (of the full matrix)
//   fem-cg      solve A x = M 1 from x = 0 by CG            rated in CG iterations/s
//   fem-eigen   the inverse power iteration: λ_min of A u = λ M u, u > 0, by CG solves
//                                                           rated in CG iterations/s; the facts say
//                                                           λ, outer and CG iterations, the residual
// --strategy picks how A (and M) are stored and multiplied: csr, every entry (csr.hpp), or
// symmetric, one triangle and the window scheme of symmetric.hpp (0.5 to 0.7 of CSR's matrix bytes
// along a curve or RCM, more than CSR's in an order that keeps neighbours far apart), or sell,
// SELL-C-σ (sell.hpp: chunks of C rows a vector, σ = --sell-sigma; rated by CSR's bytes).
// A CG that does not converge within --cg-max iterations, or an inverse iteration within 1000
// steps, is a solver failure: the record is not verified and the run exits with status 3.
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "harness/common/choice_table.hpp"
#include "harness/common/units.hpp"
#include "harness/kernel/blocks.hpp"
#include "harness/kernel/kernel.hpp"
#include "kernels/fem/fem_checks.hpp"
#include "kernels/fem/fem_point.hpp"
#include "kernels/fem/sell_setup.hpp"
#include "kernels/fem/solver.hpp"

namespace suite::fem {

namespace {

enum class Solve { spmv, cg, eigen };

// How A (and M) are stored and multiplied (--strategy). The first is the plain kernel "": its
// records keep the kernel's own name, as they did before the symmetric storage came, so that a
// history of them continues.
enum class Storage { csr, symmetric, sell };

const ChoiceTable<Storage>& storages() {
    static const ChoiceTable<Storage> table{
        "strategy",
        {{"csr", "every entry, default", Storage::csr},
         {"symmetric",
          "one triangle, the transposed half through a ring of 4096 rows a thread: about 60 % of the matrix bytes; "
          "facts: window, slots, far-entries, phases, synchronised-updates",
          Storage::symmetric},
         {"sell",
          "SELL-C-σ: chunks of C rows (the build's SIMD width) padded to their longest, rows sorted by length within "
          "--sell-sigma rows; rated by CSR's bytes; facts: sell-bytes-per-nnz, padding, sell-c, sell-sigma",
          Storage::sell}}};
    return table;
}

Storage storage_of(const std::string& variant) {
    return variant.empty() ? storages().all().front().what : storages().at(variant).what;
}

// Traffic of one CG iteration by the STREAM convention: the matrix, and the vectors of the three
// fused passes (q = A p with pᵀq: p, q; x, r updates with rᵀr: x, p, r, q read, x, r written;
// p = r + βp: r, p read, p written). Flops: 2 a nonzero, 10 a row.
double cg_bytes(double matrix_bytes, std::int64_t n) { return matrix_bytes + 88.0 * static_cast<double>(n); }
double cg_flops(std::uint64_t nnz, std::int64_t n) {
    return 2.0 * static_cast<double>(nnz) + 10.0 * static_cast<double>(n);
}

class FemSolve final : public Kernel {
public:
    FemSolve(const KernelConfig& cfg, Solve solve)
        : cfg_(cfg), solve_(solve), storage_(storage_of(cfg.variant)), symmetric_(storage_ == Storage::symmetric) {}

    void setup(Arena& arena) override {
        d_.setup(arena, cfg_, FemPoint::Build::matrices);
        const int nt = cfg_.threads;
        sym_.counts = count_symmetric(d_.pattern, nt, default_window);
        if (symmetric_) setup_symmetric(arena);
        if (storage_ == Storage::sell)
            sell_ = allocate_sell(arena, d_.pattern, nt, static_cast<std::int64_t>(param(cfg_, "sell-sigma")),
                                  d_.matrices.a, solve_ == Solve::eigen ? d_.matrices.m : nullptr);
        partial_ = arena.allocate<double>("team-sums", 16 * static_cast<std::size_t>(nt));
        x_ = d_.vector(arena, "x");
        y_ = d_.vector(arena, "y");
        if (solve_ != Solve::spmv) {
            cg_ = {d_.vector(arena, "r"), d_.vector(arena, "p"), d_.vector(arena, "q")};
            f_ = d_.vector(arena, "f");
            au_ = solve_ == Solve::eigen ? d_.vector(arena, "Au") : nullptr;
        }
        if (solve_ == Solve::eigen) tol_ = param(cfg_, "tol");
        if (solve_ != Solve::spmv) {
            cg_tol_ = param(cfg_, "cg-tol");
            max_cg_ = static_cast<int>(param(cfg_, "cg-max"));
        }
        const MeshArrays m = d_.mesh;
        const Pattern p = d_.pattern;
        double* const x = x_;
        double* const y = y_;
        double* const f = f_;
        const double* const mv = d_.matrices.m;
        // x: a smooth field for the SpMV; f = M 1 for CG (y holds the 1 meanwhile).
#pragma omp parallel
        {
            const Block rb = my_block(m.nv);
            for (std::int64_t i = rb.lo; i < rb.hi; ++i) {
                x[i] = 1.0 + 0.5 * m.x[i] - 0.25 * m.y[i];
                y[i] = 1.0;
            }
#pragma omp barrier
            if (f) spmv_rows(p, mv, y, f, rb.lo, rb.hi);
        }
        // The solvers' iteration counts are part of their work: one solve now, untimed.
        if (solve_ != Solve::spmv) run(1);
        setup_cg_iterations_ = solve_ == Solve::cg ? cg_result_.iterations : eigen_.cg_iterations;
        // The result poisoned, so that verify() judges what the timed runs left.
        std::fill(y_, y_ + d_.mesh.nv, std::numeric_limits<double>::quiet_NaN());
        ran_ = false;
    }

    void run(int calls) override {
        const Operator a = op(d_.matrices.a, sym_a_, sell_.a), mv = op(d_.matrices.m, sym_m_, sell_.m);
        const std::int64_t n = d_.mesh.nv;
        ran_ = ran_ || calls > 0;
        for (int c = 0; c < calls; ++c) {
            if (solve_ == Solve::spmv) {
#pragma omp parallel
                a.apply(x_, y_, my_block(n));
                continue;
            }
#pragma omp parallel
            {
                const Block rb = my_block(n);
                TeamSum sum(partial_);
                // The solution in y; the inverse iteration's M u in x (free there).
                if (solve_ == Solve::cg) {
                    for (std::int64_t i = rb.lo; i < rb.hi; ++i) y_[i] = 0;
#pragma omp barrier
                    const CgResult r = cg_team(a, f_, y_, cg_, cg_tol_, max_cg_, sum, rb);
#pragma omp master
                    cg_result_ = r;
                } else {
                    const EigenResult r =
                        inverse_iteration_team(a, mv, {y_, f_, au_, x_, cg_}, tol_, cg_tol_, max_cg_, sum, rb);
#pragma omp master
                    eigen_ = r;
                }
            }
        }
    }

    Verification verify() override;
    std::vector<Fact> facts() const override;
    Work work() const override;

private:
    // The symmetric storage of A (and M for the inverse iteration), first touched by row blocks.
    void setup_symmetric(Arena& arena);
    Operator op(const double* csr_values, SymmetricValues sym, const double* sell) const {
        if (storage_ == Storage::sell) return Operator::of_sell(sell_.pattern, sell);
        return symmetric_ ? Operator::of_symmetric(sym_, sym) : Operator::of_csr(d_.pattern, csr_values);
    }
    double matrix_bytes() const { return symmetric_ ? sym_.counts.matrix_bytes() : csr_bytes(d_.nnz(), d_.mesh.nv); }

    KernelConfig cfg_;
    Solve solve_;
    Storage storage_;
    bool symmetric_;
    FemPoint d_;
    SymmetricPattern sym_;  // counts always (the record's statistics); arrays for symmetric only
    SymmetricValues sym_a_, sym_m_;
    SellStorage sell_;  // --strategy=sell only
    double* partial_ = nullptr;
    double *x_ = nullptr, *y_ = nullptr, *f_ = nullptr, *au_ = nullptr;
    CgVectors cg_;
    double tol_ = 0, cg_tol_ = 0;
    int max_cg_ = 0;
    CgResult cg_result_;
    EigenResult eigen_;
    long setup_cg_iterations_ = 0;
    bool ran_ = false;  // a run() since setup: the solver results below are its
};

void FemSolve::setup_symmetric(Arena& arena) {
    const SymmetricCounts& c = sym_.counts;
    const std::size_t k = static_cast<std::size_t>(c.slots), n = static_cast<std::size_t>(c.n);
    sym_.col = arena.allocate<std::uint32_t>("sym-col", n * k + 1);
    // Far parts may be empty; the arena is asked for one element at least.
    sym_.far_row = arena.allocate<std::uint32_t>("sym-far-row", static_cast<std::size_t>(c.far_rows) + 1);
    sym_.far_ptr = arena.allocate<std::uint32_t>("sym-far-ptr", static_cast<std::size_t>(c.far_rows) + 1);
    sym_.far_col = arena.allocate<std::uint32_t>("sym-far-col", c.far_nnz + 1);
    sym_.ring_stride = ring_stride_for(c.window);
    sym_.ring = arena.allocate<double>("sym-ring", static_cast<std::size_t>(sym_.ring_stride * c.threads));
    fill_symmetric(d_.pattern, sym_);
    auto values = [&](const char* name, const double* full) {
        double* near = arena.allocate<double>(std::string("sym-") + name, n * (k + 1));
        double* far = arena.allocate<double>(std::string("sym-far-") + name, c.far_nnz + 1);
        // First touch by the rows' threads, then the values (serially: setup).
        const SymmetricPattern& sp = sym_;
#pragma omp parallel
        {
            const Block b = my_block(c.n);
            std::fill(near + (sp.counts.slots + 1) * b.lo, near + (sp.counts.slots + 1) * b.hi, 0.0);
        }
        const std::string wrong = fill_symmetric_values(d_.pattern, full, sym_, near, far);
        if (!wrong.empty()) throw UsageError(cfg_.access.name + " " + name + ": " + wrong);
        return SymmetricValues{near, far};
    };
    sym_a_ = values("A", d_.matrices.a);
    if (solve_ == Solve::eigen) sym_m_ = values("M", d_.matrices.m);
}

Verification FemSolve::verify() {
    const Pattern& p = d_.pattern;
    const double* a = d_.matrices.a;
    const std::int64_t n = d_.mesh.nv;
    Verification v;
    v.passed = true;
    std::string what;
    auto fail = [&](const std::string& why) {
        if (v.passed) what = "FAILED: " + why;
        v.passed = false;
    };
    if (solve_ == Solve::spmv && symmetric_) {
        std::string figures;
        const std::string wrong = check_symmetric_product(p, a, sym_, sym_a_, x_, y_, figures);
        if (!wrong.empty()) fail(wrong);
        if (v.passed) what = figures;
    } else if (solve_ == Solve::spmv && storage_ == Storage::sell) {
        std::string figures;
        const std::string wrong = check_sell_product(p, a, sell_.pattern, sell_.a, x_, y_, figures);
        if (!wrong.empty()) fail(wrong);
        if (v.passed) what = figures;
    } else if (solve_ == Solve::spmv) {
        // The same rows in the same order, serially: equal to the last bit whatever the team.
        std::vector<double> ref(static_cast<std::size_t>(n));
        spmv_rows(p, a, x_, ref.data(), 0, n);
        for (std::int64_t i = 0; i < n && v.passed; ++i)
            if (ref[static_cast<std::size_t>(i)] != y_[i])
                fail("y[" + std::to_string(i) + "] = " + format_number(y_[i]) + ", serial " +
                     format_number(ref[static_cast<std::size_t>(i)]));
        if (v.passed) what = "y = A x equals a serial replay exactly";
    } else {
        // The true residual of what the solver returns, by its own SpMV.
        const double* sol = y_;
        std::vector<double> t(static_cast<std::size_t>(n)), t2(static_cast<std::size_t>(n));
        spmv_rows(p, a, sol, t.data(), 0, n);
        const bool cg = solve_ == Solve::cg;
        check_solve_outcome({ran_, cg, cg_result_, eigen_, setup_cg_iterations_, cg_tol_, tol_, max_cg_},
                            v.solver_failed, fail);
        if (cg) {
            std::string figures;
            const std::string wrong = check_cg_solution(p, a, f_, sol, cg_result_, cg_tol_, figures);
            if (!wrong.empty()) fail(wrong);
            if (v.passed) what = figures;
        } else {
            spmv_rows(p, d_.matrices.m, sol, t2.data(), 0, n);
            double res = 0, ref = 0, num = 0, den = 0;
            std::int64_t negative = 0;
            for (std::int64_t i = 0; i < n; ++i) {
                const double au = t[static_cast<std::size_t>(i)], mu = t2[static_cast<std::size_t>(i)];
                res += (au - eigen_.lambda * mu) * (au - eigen_.lambda * mu);
                ref += eigen_.lambda * eigen_.lambda * mu * mu;
                num += sol[i] * au;
                den += sol[i] * mu;
                if (!(sol[i] > 0)) ++negative;
            }
            const double rq = num / den, rel = std::sqrt(res / ref);
            if (!(std::fabs(rq - eigen_.lambda) <= 1e-9 * std::fabs(rq)))
                fail("λ = " + format_number(eigen_.lambda) + ", the Rayleigh quotient of u is " + format_number(rq));
            if (negative)
                fail(std::to_string(negative) +
                     " entries of the eigenvector are not positive (it should have one sign)");
            if (!(rel <= 1e-3)) fail("||A u - λ M u|| / ||λ M u|| = " + format_number(rel));
            const std::string agree =
                !v.passed
                    ? ""
                    : check_same_lambda(d_.spec + " delta=" + format_number(d_.delta) + " tol=" + format_number(tol_),
                                        cfg_.access.name, eigen_.lambda);
            if (!agree.empty()) fail(agree);
            if (v.passed)
                what = "λ = " + format_number(eigen_.lambda) +
                       " is the Rayleigh quotient of u, u > 0, ||A u - λ M u|| / ||λ M u|| = " + format_number(rel) +
                       ", λ the same as every other ordering's of this run (1e-7)";
        }
    }
    v.detail = d_.describe(cfg_) + what;
    return v;
}

// The solver's figures, then the matrix's: the bytes a nonzero of the full matrix each format
// moves (so that a fraction of a ceiling is taken of what this format reads), and for the
// symmetric storage its window, the share of far entries, its phases and synchronised updates.
std::vector<Fact> FemSolve::facts() const {
    std::vector<Fact> out;
    if (solve_ == Solve::cg)
        out = {{"iterations", static_cast<double>(cg_result_.iterations), "CG iterations"},
               {"residual", cg_result_.relative_residual, "||r||/||f||"}};
    if (solve_ == Solve::eigen)
        out = {{"lambda", eigen_.lambda, ""},
               {"iterations", static_cast<double>(eigen_.iterations), "inverse iterations"},
               {"cg-iterations", static_cast<double>(eigen_.cg_iterations), "CG iterations"},
               {"residual", eigen_.residual, "||Au-λMu||/||λMu||"}};
    const SymmetricCounts& c = sym_.counts;
    const double nz = static_cast<double>(c.nnz);
    out.push_back({"csr-bytes-per-nnz", csr_bytes(c.nnz, c.n) / nz, "B"});
    out.push_back({"symmetric-bytes-per-nnz", c.matrix_bytes() / nz, "B"});
    if (symmetric_) {
        out.push_back({"window", static_cast<double>(c.window), "rows"});
        out.push_back({"slots", static_cast<double>(c.slots), "near entries a row"});
        out.push_back({"far-entries", static_cast<double>(c.far_nnz) / nz, "of the nonzeros"});
        out.push_back({"phases", c.threads > 1 ? 2.0 : 1.0, "a product"});
        out.push_back({"synchronised-updates", static_cast<double>(c.threads - 1) * static_cast<double>(c.window - 1),
                       "a product"});
    }
    if (storage_ == Storage::sell) add_sell_facts(sell_, out);
    return out;
}

// SpMV: the matrix (in the format's bytes) and the two vectors once (STREAM convention: the
// minimal traffic; the symmetric ring stays in cache); the hardware estimate adds y's
// write-allocate. CG: cg_bytes a iteration. The inverse iteration:
// its CG iterations, and per outer step four SpMVs (M u, A u and M u for λ) and the vector passes.
Work FemSolve::work() const {
    const std::uint64_t nz = d_.nnz();
    const std::int64_t n = d_.mesh.nv;
    const double nd = static_cast<double>(n);
    Work w;
    const double matrix_pass = matrix_bytes() + 16 * nd;
    if (solve_ == Solve::spmv) {
        w.units = static_cast<double>(nz);
        w.flops = 2.0 * static_cast<double>(nz);
        w.stream_bytes = matrix_pass;
        w.hardware_bytes = matrix_pass + 8 * nd;
    } else {
        const double its = static_cast<double>(setup_cg_iterations_);
        const double outer = solve_ == Solve::eigen ? static_cast<double>(eigen_.iterations) : 0;
        w.units = its;
        w.flops = its * cg_flops(nz, n) + outer * (3 * 2.0 * static_cast<double>(nz) + 8 * nd);
        w.stream_bytes = its * cg_bytes(matrix_bytes(), n) + matrix_pass + outer * (3 * matrix_pass + 48 * nd);
        w.hardware_bytes = w.stream_bytes + its * 32 * nd;  // the write-allocate of q, and of x, r, p rewritten
    }
    const int vectors = solve_ == Solve::spmv ? 2 : solve_ == Solve::cg ? 6 : 7;
    double symmetric = 0;  // the symmetric or SELL arrays, beside the CSR ones the kernel keeps
    if (symmetric_)
        symmetric = sym_.counts.matrix_bytes() +
                    (solve_ == Solve::eigen ? 8.0 * static_cast<double>((sym_.counts.slots + 1) * sym_.counts.n +
                                                                        static_cast<std::int64_t>(sym_.counts.far_nnz))
                                            : 0.0);
    if (storage_ == Storage::sell) symmetric = sell_.footprint_bytes();
    w.footprint_bytes =
        static_cast<std::uint64_t>(csr_bytes(nz, n) + 8.0 * static_cast<double>(nz) + 8.0 * vectors * nd + 16 * nd +
                                   12.0 * static_cast<double>(d_.mesh.ne) + symmetric);
    return w;
}

void validate_solve(const KernelConfig& cfg, const std::string& name, Solve s) {
    validate_solver_params(cfg, name, s != Solve::spmv, s == Solve::eigen);
    validate_sell_sigma(param(cfg, "sell-sigma"), name);
    validate_fem(cfg, name, true);
}

bool register_solve(const char* name, Solve s, const char* formula, const char* unit, const char* notes) {
    KernelEntry e;
    e.info.name = name;
    e.info.group = "fem";
    e.info.formula = formula;
    e.info.unit = unit;
    e.info.variants = {""};
    for (std::size_t i = 1; i < storages().all().size(); ++i) e.info.variants.push_back(storages().all()[i].name);
    e.info.variant_option = "strategy";
    e.info.plain_variant_name = storages().all().front().name;
    e.info.params = {delta_param()};
    for (ParamInfo& p : solver_params(s != Solve::spmv, s == Solve::eigen)) e.info.params.push_back(std::move(p));
    e.info.params.push_back(sell_sigma_param());
    // Per unit: a nonzero's value and column (SpMV); a CG iteration's per-row bytes (about 7 nonzeros a row).
    e.info.read_bytes_per_unit = s == Solve::spmv ? 12 : 0;
    e.info.flops_per_unit = s == Solve::spmv ? 2 : 0;
    e.info.notes = std::string(notes) + "; --strategy=" + storages().described();
    set_mesh_sizing(e);
    e.make = [s](const KernelConfig& cfg) { return std::make_unique<FemSolve>(cfg, s); };
    e.validate = [name = std::string(name), s](const KernelConfig& cfg) { validate_solve(cfg, name, s); };
    return register_kernel(std::move(e));
}

const bool registered =
    register_solve("fem-spmv", Solve::spmv, "y[i] = Σ_k A[k] x[col[k]]", "nonzero",
                   "SpMV of the P1 Helmholtz matrix A") &&
    register_solve("fem-cg", Solve::cg, "CG on A x = M 1", "iteration",
                   "unpreconditioned CG from x = 0; rated per iteration (facts: iterations, residual)") &&
    register_solve(
        "fem-eigen", Solve::eigen, "inverse iteration: A u = λ M u", "iteration",
        "the whole inverse power iteration, rated per CG iteration (facts: λ, iterations, CG iterations, residual)");

}  // namespace

}  // namespace suite::fem
