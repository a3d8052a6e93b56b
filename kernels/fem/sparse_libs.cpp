#include "kernels/fem/sparse_libs.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

#if defined(SUITE_HAVE_SPARSE)
#include <amd.h>
#include <cholmod.h>
#include <metis.h>
#endif

namespace suite::fem {

#if !defined(SUITE_HAVE_SPARSE)

#ifndef SUITE_SPARSE_MISSING
#define SUITE_SPARSE_MISSING "SuiteSparse (libsuitesparse-dev) and METIS (libmetis-dev)"
#endif
std::string sparse_libs_missing() { return SUITE_SPARSE_MISSING; }
std::vector<std::pair<std::string, std::string>> sparse_lib_versions() { return {}; }
namespace {
[[noreturn]] void absent() { throw std::logic_error("suite matrix: built without " + sparse_libs_missing()); }
}  // namespace
std::vector<std::uint32_t> amd_order(const Csr&) { absent(); }
std::vector<std::uint32_t> nested_dissection_order(const Csr&) { absent(); }
Symbolic analyse(const Csr&) { absent(); }
Factorisation factorise(const Csr&, int) { absent(); }
void check_definite(const Csr&) { absent(); }
std::vector<double> cholesky_solve(const Csr&, const std::vector<double>&, CholeskyTimes*) { absent(); }

#else

std::string sparse_libs_missing() { return ""; }

std::vector<std::pair<std::string, std::string>> sparse_lib_versions() {
    auto v = [](int a, int b, int c) { return std::to_string(a) + "." + std::to_string(b) + "." + std::to_string(c); };
    return {{"amd", v(AMD_MAIN_VERSION, AMD_SUB_VERSION, AMD_SUBSUB_VERSION)},
            {"cholmod", v(CHOLMOD_MAIN_VERSION, CHOLMOD_SUB_VERSION, CHOLMOD_SUBSUB_VERSION)},
            {"metis", v(METIS_VER_MAJOR, METIS_VER_MINOR, METIS_VER_SUBMINOR)}};
}

namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

std::vector<std::uint32_t> from_int(const int* p, std::int64_t n) {
    std::vector<std::uint32_t> out(static_cast<std::size_t>(n));
    for (std::int64_t i = 0; i < n; ++i) out[static_cast<std::size_t>(i)] = static_cast<std::uint32_t>(p[i]);
    return out;
}

// One cholmod_common for a scope: started, told to keep the matrix's own numbering, finished.
// CHOLMOD's 64-bit interface (cholmod_l_*): the symbolic analysis of a banded or random order of
// a large mesh counts more than 2^31 factor nonzeros, which the int interface refuses.
struct Cholmod {
    cholmod_common c;
    explicit Cholmod(bool own_ordering) {
        cholmod_l_start(&c);
        c.print = 0;  // errors come back through c.status, said once by the caller
        // Always the supernodal LLᵀ: CHOLMOD's simplicial default is LDLᵀ, which factorises an
        // indefinite matrix without a word (D has negative entries); LLᵀ stops at the first
        // non-positive pivot, which is the definiteness check this command promises.
        c.supernodal = CHOLMOD_SUPERNODAL;
        if (!own_ordering) {
            c.nmethods = 1;
            c.method[0].ordering = CHOLMOD_NATURAL;
            c.postorder = 0;
        }
    }
    ~Cholmod() { cholmod_l_finish(&c); }
    Cholmod(const Cholmod&) = delete;
    Cholmod& operator=(const Cholmod&) = delete;
    void ok(const char* what) const {
        if (c.status < 0)
            throw std::runtime_error(std::string("CHOLMOD ") + what + " failed (status " + std::to_string(c.status) +
                                     ")");
    }
};

// The upper triangle of a, as CHOLMOD's symmetric CSC (CSR row i is CSC column i: same entries).
cholmod_sparse* upper(const Csr& a, cholmod_common* c) {
    std::size_t count = 0;
    for (std::int64_t i = 0; i < a.n; ++i)
        for (std::uint32_t k = a.row_ptr[i]; k < a.row_ptr[i + 1]; ++k) count += a.col[k] <= i;
    cholmod_sparse* s = cholmod_l_allocate_sparse(static_cast<std::size_t>(a.n), static_cast<std::size_t>(a.n), count,
                                                  1, 1, 1, CHOLMOD_REAL, c);
    if (!s) throw std::runtime_error("CHOLMOD could not allocate the matrix");
    auto* p = static_cast<SuiteSparse_long*>(s->p);
    auto* r = static_cast<SuiteSparse_long*>(s->i);
    double* x = static_cast<double*>(s->x);
    std::size_t t = 0;
    for (std::int64_t i = 0; i < a.n; ++i) {
        p[i] = static_cast<SuiteSparse_long>(t);
        for (std::uint32_t k = a.row_ptr[i]; k < a.row_ptr[i + 1] && a.col[k] <= i; ++k) {
            r[t] = static_cast<SuiteSparse_long>(a.col[k]);
            x[t++] = a.val[k];
        }
    }
    p[a.n] = static_cast<SuiteSparse_long>(t);
    return s;
}

}  // namespace

std::vector<std::uint32_t> amd_order(const Csr& a) {
    std::vector<int> ap(a.row_ptr.begin(), a.row_ptr.end()), ai(a.col.begin(), a.col.end()),
        p(static_cast<std::size_t>(a.n));
    double control[AMD_CONTROL], info[AMD_INFO];
    amd_defaults(control);
    const int status = ::amd_order(static_cast<int>(a.n), ap.data(), ai.data(), p.data(), control, info);
    if (status != AMD_OK && status != AMD_OK_BUT_JUMBLED)
        throw std::runtime_error("AMD failed (status " + std::to_string(status) + ")");
    return from_int(p.data(), a.n);
}

std::vector<std::uint32_t> nested_dissection_order(const Csr& a) {
    std::vector<idx_t> xadj(static_cast<std::size_t>(a.n) + 1, 0), adj;
    adj.reserve(a.nnz());
    for (std::int64_t i = 0; i < a.n; ++i) {
        for (std::uint32_t k = a.row_ptr[i]; k < a.row_ptr[i + 1]; ++k)
            if (a.col[k] != i) adj.push_back(static_cast<idx_t>(a.col[k]));
        xadj[i + 1] = static_cast<idx_t>(adj.size());
    }
    idx_t n = static_cast<idx_t>(a.n);
    idx_t options[METIS_NOPTIONS];
    METIS_SetDefaultOptions(options);
    options[METIS_OPTION_NUMBERING] = 0;
    std::vector<idx_t> perm(static_cast<std::size_t>(a.n)), iperm(static_cast<std::size_t>(a.n));
    const int status = METIS_NodeND(&n, xadj.data(), adj.data(), nullptr, options, perm.data(), iperm.data());
    if (status != METIS_OK) throw std::runtime_error("METIS_NodeND failed (status " + std::to_string(status) + ")");
    // METIS's manual: row i of the permuted matrix is row perm[i] of the original, which is this
    // file's perm[new] = old. (The other array read as that order gives a fill close to a random
    // numbering's: the tests check that nested dissection's fill is below RCM's.)
    return from_int(perm.data(), a.n);
}

Symbolic analyse(const Csr& a) {
    Cholmod ch(false);
    cholmod_sparse* s = upper(a, &ch.c);
    const auto t0 = Clock::now();
    cholmod_factor* l = cholmod_l_analyze(s, &ch.c);
    Symbolic r;
    r.seconds = since(t0);
    cholmod_l_free_sparse(&s, &ch.c);
    ch.ok("analyze");
    r.factor_nnz = ch.c.lnz;
    r.flops = ch.c.fl;
    cholmod_l_free_factor(&l, &ch.c);
    return r;
}

Factorisation factorise(const Csr& a, int reps) {
    Cholmod ch(false);
    cholmod_sparse* s = upper(a, &ch.c);
    Factorisation f;
    auto t0 = Clock::now();
    cholmod_factor* l = cholmod_l_analyze(s, &ch.c);
    f.analyse_seconds = since(t0);
    ch.ok("analyze");
    f.factor_nnz = ch.c.lnz;
    f.flops = ch.c.fl;
    cholmod_dense* ones = cholmod_l_ones(static_cast<std::size_t>(a.n), 1, CHOLMOD_REAL, &ch.c);
    cholmod_dense* b = cholmod_l_zeros(static_cast<std::size_t>(a.n), 1, CHOLMOD_REAL, &ch.c);
    double one[2] = {1, 0}, zero[2] = {0, 0}, minus[2] = {-1, 0};
    cholmod_l_sdmult(s, 0, one, zero, ones, b, &ch.c);  // b = A 1
    cholmod_dense* x = nullptr;
    for (int r = 0; r < reps; ++r) {
        t0 = Clock::now();
        cholmod_l_factorize(s, l, &ch.c);
        f.factor_seconds.push_back(since(t0));
        if (ch.c.status == CHOLMOD_NOT_POSDEF) {
            const auto minor = static_cast<std::int64_t>(l->minor);
            if (x) cholmod_l_free_dense(&x, &ch.c);
            cholmod_l_free_dense(&ones, &ch.c);
            cholmod_l_free_dense(&b, &ch.c);
            cholmod_l_free_factor(&l, &ch.c);
            cholmod_l_free_sparse(&s, &ch.c);
            throw NotDefinite(minor, "the matrix is not positive definite: CHOLMOD stopped at column " +
                                         std::to_string(minor) + " of " + std::to_string(a.n));
        }
        ch.ok("factorize");
        if (x) cholmod_l_free_dense(&x, &ch.c);
        t0 = Clock::now();
        x = cholmod_l_solve(CHOLMOD_A, l, b, &ch.c);
        f.solve_seconds.push_back(since(t0));
        ch.ok("solve");
    }
    f.method = std::string(l->is_super ? "supernodal" : "simplicial") + (l->is_ll ? " LLᵀ" : " LDLᵀ");
    // The answer is checked, as every kernel's: x must be 1, and b - A x small.
    cholmod_dense* res = cholmod_l_copy_dense(b, &ch.c);
    cholmod_l_sdmult(s, 0, minus, one, x, res, &ch.c);  // res = b - A x
    const double* xv = static_cast<const double*>(x->x);
    for (std::int64_t i = 0; i < a.n; ++i) f.max_error = std::max(f.max_error, std::fabs(xv[i] - 1));
    f.residual = cholmod_l_norm_dense(res, 2, &ch.c) / cholmod_l_norm_dense(b, 2, &ch.c);
    cholmod_l_free_dense(&res, &ch.c);
    cholmod_l_free_dense(&x, &ch.c);
    cholmod_l_free_dense(&ones, &ch.c);
    cholmod_l_free_dense(&b, &ch.c);
    cholmod_l_free_factor(&l, &ch.c);
    cholmod_l_free_sparse(&s, &ch.c);
    return f;
}

std::vector<double> cholesky_solve(const Csr& a, const std::vector<double>& b, CholeskyTimes* times) {
    Cholmod ch(true);
    cholmod_sparse* s = upper(a, &ch.c);
    auto t0 = Clock::now();
    cholmod_factor* l = cholmod_l_analyze(s, &ch.c);
    ch.ok("analyze");
    if (times) times->analyse = since(t0);
    t0 = Clock::now();
    cholmod_l_factorize(s, l, &ch.c);
    if (times) times->factorise = since(t0);
    if (ch.c.status == CHOLMOD_NOT_POSDEF) {
        const std::int64_t minor = static_cast<std::int64_t>(l->minor);
        cholmod_l_free_factor(&l, &ch.c);
        cholmod_l_free_sparse(&s, &ch.c);
        throw NotDefinite(minor, "the matrix is not positive definite (CHOLMOD met a non-positive pivot)");
    }
    ch.ok("factorize");
    cholmod_dense* rhs = cholmod_l_zeros(static_cast<std::size_t>(a.n), 1, CHOLMOD_REAL, &ch.c);
    std::copy(b.begin(), b.end(), static_cast<double*>(rhs->x));
    t0 = Clock::now();
    cholmod_dense* x = cholmod_l_solve(CHOLMOD_A, l, rhs, &ch.c);
    ch.ok("solve");
    if (times) times->solve = since(t0);
    const double* xv = static_cast<const double*>(x->x);
    std::vector<double> out(xv, xv + a.n);
    cholmod_l_free_dense(&x, &ch.c);
    cholmod_l_free_dense(&rhs, &ch.c);
    cholmod_l_free_factor(&l, &ch.c);
    cholmod_l_free_sparse(&s, &ch.c);
    return out;
}

void check_definite(const Csr& a) {
    Cholmod ch(true);
    cholmod_sparse* s = upper(a, &ch.c);
    cholmod_factor* l = cholmod_l_analyze(s, &ch.c);
    ch.ok("analyze");
    cholmod_l_factorize(s, l, &ch.c);
    const bool bad = ch.c.status == CHOLMOD_NOT_POSDEF;
    const std::int64_t minor = static_cast<std::int64_t>(l->minor);
    cholmod_l_free_factor(&l, &ch.c);
    cholmod_l_free_sparse(&s, &ch.c);
    if (bad)
        throw NotDefinite(
            minor, "the matrix is not positive definite (CHOLMOD, in its own ordering, met a non-positive pivot)");
    ch.ok("factorize");
}

#endif

}  // namespace suite::fem
