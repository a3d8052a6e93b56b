// The solver kernels with their rows shared out over the ranks of the run (KernelConfig::
// communicator(): one rank in a plain run, every rank of `suite-mpi`), each rank on its own rows
// with its halo exchanged before every product (distributed.hpp). One repetition, on every rank:
//   fem-spmv-dist    x's halo in, y = A x on the owned rows          rated in the rank's nonzeros/s
//   fem-cg-dist      A x = M 1 from x = 0 by CG, dots summed over the ranks      CG iterations/s
//   fem-eigen-dist   the inverse power iteration (as fem-eigen)                   CG iterations/s
// --strategy=curve (default) or metis picks the partition (partition.hpp). The set-up is
// replicated: every rank loads the whole mesh in the point's ordering, assembles the whole of A and
// M serially (the matrices of fem-spmv/fem-eigen, to the bit), computes the same partition and keeps
// its own rows, copied into the arena and first touched by the threads that compute on them.
// Work and bytes are the rank's own share, so that the ranks' records add up to the whole.
// verify() is collective (distributed products and sums): every rank calls it in the same order.
#include <omp.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

#include "harness/common/units.hpp"
#include "harness/kernel/blocks.hpp"
#include "harness/kernel/kernel.hpp"
#include "kernels/fem/assembly.hpp"
#include "kernels/fem/distributed.hpp"
#include "kernels/fem/fem_checks.hpp"
#include "kernels/fem/fem_mesh.hpp"
#include "kernels/fem/fem_point.hpp"
#include "kernels/fem/partition.hpp"

namespace suite::fem {

namespace {

enum class DistSolve { spmv, cg, eigen };

class FemDist final : public Kernel {
public:
    FemDist(const KernelConfig& cfg, DistSolve solve)
        : cfg_(cfg), solve_(solve), scheme_(parse_partition_scheme(cfg.variant)), comm_(cfg.communicator()) {}

    void setup(Arena& arena) override;
    void run(int calls) override;
    Verification verify() override;
    std::vector<Fact> facts() const override;
    Work work() const override;

private:
    // owned (+ halo) doubles in the arena, zero, first touched by row blocks; the halo by the last thread.
    double* vector(Arena& arena, const std::string& name, bool with_halo) const;
    std::string describe() const;

    KernelConfig cfg_;
    DistSolve solve_;
    PartitionScheme scheme_;
    const Comm& comm_;
    std::string spec_;
    std::int64_t nv_ = 0, ne_ = 0, n_ = 0, halo_ = 0;
    std::uint64_t nnz_ = 0;
    PartitionQuality quality_;
    std::vector<std::uint32_t> global_;  // the global row of each owned row
    std::unique_ptr<DistributedSolver> solver_;
    // fem-spmv-dist's reference: the global matrix and x (heap, set-up data; the timed arrays are the arena's).
    AssembledCsr serial_;
    std::vector<double> serial_x_;
    double *a_ = nullptr, *m_ = nullptr, *x_ = nullptr, *y_ = nullptr, *f_ = nullptr, *au_ = nullptr;
    const std::uint32_t *row_ptr_ = nullptr, *col_ = nullptr;  // the rank's rows, local columns
    CgVectors cg_;
    double tol_ = 0, cg_tol_ = 0;
    int max_cg_ = 0;
    CgResult cg_result_;
    EigenResult eigen_;
    long setup_cg_iterations_ = 0;
    std::int64_t sent_ = 0;
    bool ran_ = false;  // a run() since setup: the solver results are its
};

double* FemDist::vector(Arena& arena, const std::string& name, bool with_halo) const {
    const std::int64_t n = n_, total = n_ + (with_halo ? halo_ : 0);
    double* v = arena.allocate<double>(name, static_cast<std::size_t>(std::max<std::int64_t>(total, 1)));
#pragma omp parallel
    {
        const Block rb = my_block(n);
        std::fill(v + rb.lo, v + rb.hi, 0.0);
        if (omp_get_thread_num() == omp_get_num_threads() - 1) std::fill(v + n, v + total, 0.0);
    }
    return v;
}

void FemDist::setup(Arena& arena) {
    spec_ = mesh_spec_of(cfg_);
    const mesh::Mesh mesh = load_fem_mesh(spec_, cfg_.access.name, cfg_.seed);
    nv_ = static_cast<std::int64_t>(mesh.vertices());
    ne_ = static_cast<std::int64_t>(mesh.elements());
    AssembledCsr global =
        assemble_reference({nv_, ne_, mesh.x.data(), mesh.y.data(), mesh.conn.data()}, param(cfg_, "delta"));
    const Pattern gp = global.pattern();
    const Partition part = make_partition(scheme_, gp, comm_.size(), cfg_.seed);
    quality_ = partition_quality(gp, part);
    const bool with_m = solve_ != DistSolve::spmv;
    LocalMatrix lm = local_matrix(gp, global.a.data(), with_m ? global.m.data() : nullptr, part, comm_.rank());
    n_ = lm.owned;
    halo_ = lm.halo;
    nnz_ = lm.nnz();
    global_.assign(lm.global.begin(), lm.global.begin() + n_);

    // The rank's rows in the arena, each row block's entries first touched by the thread that multiplies them.
    auto* row_ptr = arena.allocate<std::uint32_t>("row-ptr", static_cast<std::size_t>(n_) + 1);
    auto* col = arena.allocate<std::uint32_t>("col", std::max<std::size_t>(nnz_, 1));
    a_ = arena.allocate<double>("A", std::max<std::size_t>(nnz_, 1));
    m_ = with_m ? arena.allocate<double>("M", std::max<std::size_t>(nnz_, 1)) : nullptr;
    const std::int64_t n = n_;
    double* const a = a_;
    double* const m = m_;
    int team = 0;
#pragma omp parallel num_threads(cfg_.threads) reduction(max : team)
    {
        team = omp_get_num_threads();
        const Block rb = my_block(n);
        for (std::int64_t i = rb.lo; i < rb.hi; ++i) row_ptr[i] = lm.row_ptr[static_cast<std::size_t>(i)];
        if (omp_get_thread_num() == omp_get_num_threads() - 1) row_ptr[n] = lm.row_ptr[static_cast<std::size_t>(n)];
        for (std::uint32_t k = lm.row_ptr[static_cast<std::size_t>(rb.lo)];
             k < lm.row_ptr[static_cast<std::size_t>(rb.hi)]; ++k) {
            col[k] = lm.col[k];
            a[k] = lm.a[k];
            if (m) m[k] = lm.m[k];
        }
    }
    require_team_size(team, cfg_.threads);
    row_ptr_ = row_ptr;
    col_ = col;
    const LocalSystem sys{{n_, row_ptr, col}, a_, m_, halo_};
    solver_ = std::make_unique<DistributedSolver>(comm_, sys, HaloExchange(n_, lm.links));
    sent_ = solver_->halo().sent();

    x_ = vector(arena, "x", true);
    y_ = vector(arena, "y", true);
    if (solve_ == DistSolve::spmv) {
        // x: fem-spmv's smooth field, the global one kept for verify()'s serial product.
        serial_ = std::move(global);
        for (std::size_t g = 0; g < mesh.vertices(); ++g) serial_x_.push_back(1.0 + 0.5 * mesh.x[g] - 0.25 * mesh.y[g]);
        for (std::int64_t i = 0; i < n_; ++i) x_[i] = serial_x_[global_[static_cast<std::size_t>(i)]];
    } else {
        cg_ = {vector(arena, "r", false), vector(arena, "p", true), vector(arena, "q", false)};
        f_ = vector(arena, "f", false);
        au_ = solve_ == DistSolve::eigen ? vector(arena, "Au", false) : nullptr;
        cg_tol_ = param(cfg_, "cg-tol");
        max_cg_ = static_cast<int>(param(cfg_, "cg-max"));
        if (solve_ == DistSolve::eigen) tol_ = param(cfg_, "tol");
        // f = M 1 (y holds the 1 meanwhile), by the distributed product: the serial f's rows to the bit.
        std::fill(y_, y_ + n_ + halo_, 1.0);
        solver_->spmv(m_, y_, f_);
        // The solvers' iteration counts are part of their work: one solve now, untimed.
        run(1);
        setup_cg_iterations_ = solve_ == DistSolve::cg ? cg_result_.iterations : eigen_.cg_iterations;
    }
    // The result poisoned, so that verify() judges what the timed runs left; x's halo too, so that
    // a product that skipped the exchange cannot pass.
    std::fill(y_, y_ + n_ + halo_, std::numeric_limits<double>::quiet_NaN());
    std::fill(x_ + n_, x_ + n_ + halo_, std::numeric_limits<double>::quiet_NaN());
    ran_ = false;
}

void FemDist::run(int calls) {
    ran_ = ran_ || calls > 0;
    for (int c = 0; c < calls; ++c) {
        if (solve_ == DistSolve::spmv) {
            solver_->spmv(a_, x_, y_);
        } else if (solve_ == DistSolve::cg) {
            const std::int64_t n = n_;
            double* const y = y_;
#pragma omp parallel
            {
                const Block rb = my_block(n);
                std::fill(y + rb.lo, y + rb.hi, 0.0);
            }
            cg_result_ = solver_->cg(f_, y_, cg_, cg_tol_, max_cg_);
        } else {
            // The eigenvector in y; M u in x (free there).
            eigen_ = solver_->inverse_iteration({y_, f_, au_, x_, cg_}, tol_, cg_tol_, max_cg_);
        }
    }
}

std::string FemDist::describe() const {
    return "mesh " + spec_ + " (" + std::to_string(ne_) + " triangles, " + std::to_string(nv_) + " vertices), " +
           cfg_.access.name + ", " + partition_scheme_name(scheme_) + " partition, rank " +
           std::to_string(comm_.rank()) + " of " + std::to_string(comm_.size()) + " (" + std::to_string(n_) +
           " rows, halo " + std::to_string(halo_) + "): ";
}

Verification FemDist::verify() {
    Verification v;
    v.passed = true;
    std::string what;
    auto fail = [&](const std::string& why) {
        if (v.passed) what = "FAILED: " + why;
        v.passed = false;
    };
    const std::size_t n = static_cast<std::size_t>(n_);
    if (solve_ == DistSolve::spmv) {
        // Every owned row against the same row of the serial product of the global matrix, to the bit.
        const Pattern gp = serial_.pattern();
        std::vector<double> ref(static_cast<std::size_t>(nv_));
        std::int64_t bad = 0;
        for (std::size_t i = 0; i < n; ++i) {
            const std::int64_t g = global_[i];
            spmv_rows(gp, serial_.a.data(), serial_x_.data(), ref.data(), g, g + 1);
            if (ref[static_cast<std::size_t>(g)] == y_[i]) continue;
            if (bad++ == 0)
                fail("y of global row " + std::to_string(g) + " = " + format_number(y_[i]) + ", serial " +
                     format_number(ref[static_cast<std::size_t>(g)]));
        }
        if (comm_.max(bad) > 0 && bad == 0) fail("another rank's rows differ from the serial product");
        if (v.passed) what = "y = A x on every rank's rows equals the serial product of the global matrix exactly";
        v.detail = describe() + what;
        return v;
    }
    // The true residual of what the solver left, by a distributed product of its own.
    std::vector<double> au(n), mu(n);
    solver_->spmv(a_, y_, au.data());
    if (solve_ == DistSolve::eigen) solver_->spmv(m_, y_, mu.data());
    const bool cg = solve_ == DistSolve::cg;
    const SolveOutcome outcome{ran_, cg, cg_result_, eigen_, setup_cg_iterations_, cg_tol_, tol_, max_cg_};
    const long its = outcome.cg_iterations();
    const std::int64_t most = comm_.max(its), least = -comm_.max(-its);
    check_solve_outcome(outcome, v.solver_failed, fail);
    if (most != least)
        fail("the ranks took from " + std::to_string(least) + " to " + std::to_string(most) +
             " CG iterations; they must agree");
    if (cg) {
        // ||f - A x||², ||f||², || |A| |x| ||² (the halo of x is there: the product exchanged it).
        std::array<double, 3> s{0, 0, 0};
        std::int64_t longest = 0;
        for (std::size_t i = 0; i < n; ++i) {
            const double r = f_[i] - au[i];
            double abs_ax = 0;
            for (std::uint32_t k = row_ptr_[i]; k < row_ptr_[i + 1]; ++k) abs_ax += std::fabs(a_[k] * y_[col_[k]]);
            s[0] += r * r;
            s[1] += f_[i] * f_[i];
            s[2] += abs_ax * abs_ax;
            longest = std::max<std::int64_t>(longest, row_ptr_[i + 1] - row_ptr_[i]);
        }
        comm_.sum(s);
        const double rel = std::sqrt(s[0] / s[1]),
                     margin = cg_rounding_margin(its, comm_.max(longest), std::sqrt(s[2]), std::sqrt(s[1]));
        const std::string wrong = judge_cg_residuals(rel, cg_result_.relative_residual, cg_tol_, margin);
        if (!wrong.empty()) fail(wrong);
        if (v.passed)
            what = "||f - A x|| / ||f|| = " + format_number(rel) +
                   " recomputed by a distributed product, within --cg-tol=" + format_number(cg_tol_) + " + " +
                   format_number(margin) + " (rounding), " + std::to_string(its) + " iterations on every rank";
    } else {
        const double lambda = eigen_.lambda;
        std::array<double, 5> s{0, 0, 0, 0, 0};  // ||A u - λ M u||², ||λ M u||², uᵀAu, uᵀMu, entries not > 0
        for (std::size_t i = 0; i < n; ++i) {
            s[0] += (au[i] - lambda * mu[i]) * (au[i] - lambda * mu[i]);
            s[1] += lambda * lambda * mu[i] * mu[i];
            s[2] += y_[i] * au[i];
            s[3] += y_[i] * mu[i];
            if (!(y_[i] > 0)) s[4] += 1;
        }
        comm_.sum(s);
        const double rq = s[2] / s[3], rel = std::sqrt(s[0] / s[1]);
        if (!(std::fabs(rq - lambda) <= 1e-9 * std::fabs(rq)))
            fail("λ = " + format_number(lambda) + ", the Rayleigh quotient of u is " + format_number(rq));
        if (s[4] > 0)
            fail(format_number(s[4]) + " entries of the eigenvector are not positive (it should have one sign)");
        if (!(rel <= 1e-3)) fail("||A u - λ M u|| / ||λ M u|| = " + format_number(rel));
        const std::string key = spec_ + " delta=" + format_number(param(cfg_, "delta")) + " tol=" + format_number(tol_);
        const std::string agree =
            !v.passed ? "" : check_same_lambda(key, cfg_.access.name + "/" + partition_scheme_name(scheme_), lambda);
        if (!agree.empty()) fail(agree);
        if (v.passed)
            what = "λ = " + format_number(lambda) +
                   " is the Rayleigh quotient of u (distributed), u > 0, ||A u - λ M u|| / ||λ M u|| = " +
                   format_number(rel) +
                   ", the same CG count on every rank, λ the same as every other ordering's and partition's of this "
                   "run (1e-7)";
    }
    v.detail = describe() + what;
    return v;
}

std::vector<Fact> FemDist::facts() const {
    const std::size_t r = static_cast<std::size_t>(comm_.rank());
    std::vector<Fact> f{{"ranks", static_cast<double>(comm_.size()), ""},
                        {"rows", static_cast<double>(n_), "rows"},
                        {"halo", static_cast<double>(quality_.halo[r]), "values"},
                        {"neighbours", static_cast<double>(quality_.neighbours[r]), "ranks"},
                        {"edge-cut", static_cast<double>(quality_.edge_cut), "edges"},
                        {"imbalance-rows", quality_.imbalance_rows, "max/mean"},
                        {"imbalance-nnz", quality_.imbalance_nnz, "max/mean"}};
    if (solve_ == DistSolve::cg) {
        f.push_back({"iterations", static_cast<double>(cg_result_.iterations), "CG iterations"});
        f.push_back({"residual", cg_result_.relative_residual, "||r||/||f||"});
    } else if (solve_ == DistSolve::eigen) {
        f.push_back({"lambda", eigen_.lambda, ""});
        f.push_back({"iterations", static_cast<double>(eigen_.iterations), "inverse iterations"});
        f.push_back({"cg-iterations", static_cast<double>(eigen_.cg_iterations), "CG iterations"});
        f.push_back({"residual", eigen_.residual, "||Au-λMu||/||λMu||"});
    }
    return f;
}

// The rank's share, as fem_solve.cpp counts the whole: its CSR rows, the vectors over its rows, and
// per exchange the halo values received (8 B each). The hardware estimate adds y's write-allocate
// and the gather of the values sent (read, then written into the send buffer).
Work FemDist::work() const {
    const double nd = static_cast<double>(n_), nz = static_cast<double>(nnz_), halo = 8.0 * static_cast<double>(halo_);
    const double matrix_pass = csr_bytes(nnz_, n_) + 16 * nd;
    const double gather = 16.0 * static_cast<double>(sent_);
    Work w;
    if (solve_ == DistSolve::spmv) {
        w.units = nz;
        w.flops = 2 * nz;
        w.stream_bytes = matrix_pass + halo;
        w.hardware_bytes = w.stream_bytes + 8 * nd + gather;
    } else {
        // Exchanges: one a CG iteration and one a solve's start; the inverse iteration's outer steps
        // add the products M u and the Rayleigh quotient's, and the first and last A u, M u.
        const double its = static_cast<double>(setup_cg_iterations_);
        const double outer = solve_ == DistSolve::eigen ? static_cast<double>(eigen_.iterations) : 0;
        const double exchanges = solve_ == DistSolve::cg ? its + 1 : its + 3 * outer + 2;
        w.units = its;
        w.flops = its * (2 * nz + 10 * nd) + outer * (3 * 2 * nz + 8 * nd);
        w.stream_bytes = its * (csr_bytes(nnz_, n_) + 88 * nd) + matrix_pass + outer * (3 * matrix_pass + 48 * nd) +
                         exchanges * halo;
        w.hardware_bytes = w.stream_bytes + its * 32 * nd + exchanges * gather;
    }
    const int with_halo = solve_ == DistSolve::spmv ? 2 : 3, owned_only = solve_ == DistSolve::spmv ? 0
                                                                          : solve_ == DistSolve::cg ? 3
                                                                                                    : 4;
    const double matrices = solve_ == DistSolve::spmv ? 1 : 2;
    w.footprint_bytes =
        static_cast<std::uint64_t>(csr_bytes(nnz_, n_) + 8 * (matrices - 1) * nz +
                                   8 * with_halo * (nd + static_cast<double>(halo_)) + 8 * owned_only * nd);
    return w;
}

void dist_validate(const KernelConfig& cfg, const std::string& name, DistSolve s) {
    if (parse_partition_scheme(cfg.variant) == PartitionScheme::metis) require_metis();
    validate_solver_params(cfg, name, s != DistSolve::spmv, s == DistSolve::eigen);
    validate_fem(cfg, name, true);
    const std::string spec = mesh_spec_of(cfg);
    const std::uint64_t vertices = mesh::mesh_counts(mesh::parse_mesh_spec(spec)).vertices,
                        ranks = static_cast<std::uint64_t>(cfg.communicator().size());
    if (vertices < ranks)
        throw UsageError(name + " on --mesh=" + spec + ": " + std::to_string(vertices) +
                         " vertices cannot give each of " + std::to_string(ranks) +
                         " ranks a row; use a larger mesh or fewer ranks");
}

bool dist_register(const char* name, DistSolve s, const char* formula, const char* unit, const std::string& notes) {
    KernelEntry e;
    e.info.name = name;
    e.info.group = "fem";
    e.info.formula = formula;
    e.info.unit = unit;
    e.info.variants = partition_schemes().names();
    e.info.variant_option = "strategy";
    e.info.default_variants = {partition_scheme_name(PartitionScheme::curve)};
    e.info.params = {delta_param()};
    for (ParamInfo& p : solver_params(s != DistSolve::spmv, s == DistSolve::eigen))
        e.info.params.push_back(std::move(p));
    e.info.read_bytes_per_unit = s == DistSolve::spmv ? 12 : 0;
    e.info.flops_per_unit = s == DistSolve::spmv ? 2 : 0;
    e.info.notes = notes + "; --strategy=" + partition_schemes().described() +
                   " (default curve); set-up replicated: every "
                   "rank builds the whole mesh and matrices, partitions them and keeps its own rows; facts: ranks, "
                   "rows, halo, neighbours, "
                   "edge-cut, imbalance-rows, imbalance-nnz";
    set_mesh_sizing(e);
    e.make = [s](const KernelConfig& cfg) { return std::make_unique<FemDist>(cfg, s); };
    e.validate = [name = std::string(name), s](const KernelConfig& cfg) { dist_validate(cfg, name, s); };
    return register_kernel(std::move(e));
}

const bool dist_registered =
    dist_register("fem-spmv-dist", DistSolve::spmv, "y[i] = Σ_k A[k] x[col[k]], i the rank's rows", "nonzero",
                  "fem-spmv on the rank's rows after a halo exchange") &&
    dist_register(
        "fem-cg-dist", DistSolve::cg, "CG on A x = M 1 over the ranks", "iteration",
        "fem-cg over the ranks: a halo exchange a product, dots summed over the ranks (facts: iterations, residual)") &&
    dist_register("fem-eigen-dist", DistSolve::eigen, "inverse iteration: A u = λ M u over the ranks", "iteration",
                  "fem-eigen over the ranks, rated per CG iteration (facts: λ, iterations, CG iterations, residual)");

}  // namespace

}  // namespace suite::fem
