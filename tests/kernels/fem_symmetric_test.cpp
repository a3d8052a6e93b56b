// The symmetric storage and its window scheme (kernels/fem/symmetric.hpp) on a real mesh: every
// entry applied once, the product equal to the full CSR one on every ordering, team size and
// window (far entries and spills included), race-free (equal to its serial replay to the bit), the
// ring left zero, a non-symmetric matrix refused, and CG and the inverse iteration on it agreeing
// with the CSR solvers.
#include <omp.h>

#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "harness/kernel/blocks.hpp"
#include "kernels/fem/assembly.hpp"
#include "kernels/fem/fem_checks.hpp"
#include "kernels/fem/fem_mesh.hpp"
#include "kernels/fem/solver.hpp"
#include "kernels/fem/symmetric.hpp"

namespace suite::fem {
namespace {

const std::string circle = "file:" + std::string(SUITE_SOURCE_DIR) + "/../shared/meshes/unit_circle.txt:refine=1";

struct Problem {
    mesh::Mesh mesh;
    AssembledCsr csr;
    std::vector<double> x;
};

Problem problem(const std::string& ordering) {
    Problem p;
    p.mesh = load_fem_mesh(circle, ordering, 1);
    const MeshArrays arrays{static_cast<std::int64_t>(p.mesh.vertices()), static_cast<std::int64_t>(p.mesh.elements()),
                            p.mesh.x.data(), p.mesh.y.data(), p.mesh.conn.data()};
    p.csr = assemble_reference(arrays, 0.05);
    for (std::size_t i = 0; i < p.mesh.vertices(); ++i)
        p.x.push_back(1.0 + 0.5 * p.mesh.x[i] - 0.25 * p.mesh.y[i] + 0.01 * static_cast<double>(i % 7));
    return p;
}

// y = A x by a team of `threads` on the symmetric storage.
std::vector<double> team_product(const SymmetricMatrix& s, const std::vector<double>& x, int threads) {
    std::vector<double> y(x.size(), std::nan(""));
    std::vector<int> rows_seen(x.size(), 0);
#pragma omp parallel num_threads(threads)
    {
        symmetric_product_team(s.pattern, s.values(), x.data(), y.data(),
                               [&](std::int64_t i, double) { ++rows_seen[static_cast<std::size_t>(i)]; });
    }
    for (std::size_t i = 0; i < x.size(); ++i) EXPECT_EQ(rows_seen[i], 1) << "on_row must be called once for row " << i;
    return y;
}

TEST(FemSymmetric, EveryEntryIsAppliedOnceWhateverTheWindow) {
    Problem p = problem("hilbert");
    const Pattern full = p.csr.pattern();
    for (std::int64_t w : {1, 2, 16, 4096, 1 << 30}) {
        const SymmetricCounts c = count_symmetric(full, 1, w);
        EXPECT_EQ(c.applied(), full.nnz()) << "window " << w;
        EXPECT_EQ(count_symmetric(full, 1, w, 1).applied(), full.nnz()) << "window " << w << ", one slot";
        EXPECT_LE(c.window, std::max<std::int64_t>(w, 1));
        EXPECT_EQ(c.window & (c.window - 1), 0) << "a power of two";
    }
    // A window of one row, or no slots: the diagonal alone is near, the rest is plain CSR in both rows.
    for (const SymmetricCounts& one : {count_symmetric(full, 1, 1), count_symmetric(full, 1, 4096, 0)}) {
        EXPECT_EQ(one.near_nnz, static_cast<std::uint64_t>(full.n));
        EXPECT_EQ(one.far_nnz, full.nnz() - static_cast<std::uint64_t>(full.n));
    }
    // The split counted by hand: near is the diagonal and a row's first K upper entries within W,
    // far every other entry in both rows; K covers 95 % of the rows and no fewer.
    const SymmetricCounts c = count_symmetric(full, 1, 256);
    ASSERT_EQ(c.window, 256);
    std::uint64_t near = 0;
    std::int64_t fit = 0, fit_one_less = 0;
    for (std::int64_t i = 0; i < full.n; ++i) {
        std::int64_t upper = 0;
        for (std::uint32_t k = full.row_ptr[i]; k < full.row_ptr[i + 1]; ++k)
            upper += full.col[k] > i && full.col[k] - i < 256;
        near += 1 + std::min<std::int64_t>(upper, c.slots);
        fit += upper <= c.slots;
        fit_one_less += upper <= c.slots - 1;
    }
    EXPECT_EQ(c.near_nnz, near);
    EXPECT_EQ(c.far_nnz, full.nnz() - (2 * near - static_cast<std::uint64_t>(full.n)));
    EXPECT_GE(static_cast<double>(fit), 0.95 * static_cast<double>(full.n));
    EXPECT_LT(static_cast<double>(fit_one_less), 0.95 * static_cast<double>(full.n));
    EXPECT_EQ(count_symmetric(full, 1, 256, 2).slots, 2) << "slots asked for are kept";
    // In Hilbert order nearly every entry is near: the structure well below CSR's (padding included).
    const SymmetricCounts wide = count_symmetric(full, 1, 1 << 30);
    EXPECT_LT(static_cast<double>(wide.far_nnz), 0.05 * static_cast<double>(full.nnz()));
    EXPECT_LT(wide.matrix_bytes(),
              0.85 * (12.0 * static_cast<double>(full.nnz()) + 4.0 * static_cast<double>(full.n + 1)));
}

TEST(FemSymmetric, TheWindowFitsTheSmallestThreadBlock) {
    Problem p = problem("hilbert");
    const Pattern full = p.csr.pattern();
    for (int threads : {1, 2, 3, 7, 64}) {
        const SymmetricCounts c = count_symmetric(full, threads, 1 << 30);
        std::int64_t smallest = full.n;
        for (int t = 0; t < threads; ++t)
            smallest = std::min(smallest, static_block(full.n, t, threads).hi - static_block(full.n, t, threads).lo);
        EXPECT_LE(c.window, smallest) << threads << " threads";
        EXPECT_GT(2 * c.window, smallest) << "the largest power of two that fits, " << threads << " threads";
    }
}

TEST(FemSymmetric, ProductEqualsTheFullCsrProductOnEveryOrderingTeamAndWindow) {
    for (const char* ordering : {"natural", "random", "hilbert", "rcm"}) {
        Problem p = problem(ordering);
        const Pattern full = p.csr.pattern();
        std::vector<double> ref(p.x.size());
        spmv_rows(full, p.csr.a.data(), p.x.data(), ref.data(), 0, full.n);
        for (int threads : {1, 2, 3, 4})
            for (const auto& [w, slots] : std::vector<std::pair<std::int64_t, int>>{
                     {8, -1}, {64, -1}, {4096, -1}, {4096, 0}, {4096, 1}, {4096, 3}, {4096, 4}, {4096, 8}}) {
                SCOPED_TRACE(std::string(ordering) + ", " + std::to_string(threads) + " threads, window " +
                             std::to_string(w) + ", slots " + std::to_string(slots));
                const SymmetricMatrix s = make_symmetric(full, p.csr.a.data(), threads, w, slots);
                const std::vector<double> y = team_product(s, p.x, threads);
                std::string detail;
                EXPECT_EQ(
                    check_symmetric_product(full, p.csr.a.data(), s.pattern, s.values(), p.x.data(), y.data(), detail),
                    "")
                    << detail;
                double worst = 0;
                for (std::size_t i = 0; i < y.size(); ++i)
                    worst = std::max(worst, std::fabs(y[i] - ref[i]) / std::max(1.0, std::fabs(ref[i])));
                EXPECT_LT(worst, 1e-12);
                for (double r : s.ring) ASSERT_EQ(r, 0.0) << "the ring must be left zero for the next product";
                // A second product on the same ring gives the same y to the bit.
                EXPECT_EQ(team_product(s, p.x, threads), y);
            }
    }
}

TEST(FemSymmetric, TheCheckCatchesARaceAndAWrongValue) {
    Problem p = problem("hilbert");
    const Pattern full = p.csr.pattern();
    const SymmetricMatrix s = make_symmetric(full, p.csr.a.data(), 2, 64);
    std::vector<double> y = team_product(s, p.x, 2);
    std::string detail;
    ASSERT_EQ(check_symmetric_product(full, p.csr.a.data(), s.pattern, s.values(), p.x.data(), y.data(), detail), "");
    // The second thread's first row off by a rounding: what a race on it could leave.
    const std::size_t first = static_cast<std::size_t>(static_block(full.n, 1, 2).lo);
    SymmetricMatrix copy = s;  // its pointers then aimed at its own arrays
    copy.pattern.col = copy.col.data(), copy.pattern.ring = copy.ring.data();
    copy.pattern.far_row = copy.far_row.data(), copy.pattern.far_ptr = copy.far_ptr.data(),
    copy.pattern.far_col = copy.far_col.data();
    y[first] *= 1 + 1e-9;
    EXPECT_NE(check_symmetric_product(full, p.csr.a.data(), s.pattern, s.values(), p.x.data(), y.data(), detail)
                  .find("serial replay"),
              std::string::npos);
    // A value stored wrong: the replay agrees with the team, the full product does not.
    copy.near[static_cast<std::size_t>(copy.pattern.counts.slots + 1) * first + 1] *=
        1.001;  // its first near upper value
    const std::vector<double> y2 = team_product(copy, p.x, 2);
    EXPECT_NE(check_symmetric_product(full, p.csr.a.data(), copy.pattern, copy.values(), p.x.data(), y2.data(), detail)
                  .find("full CSR product"),
              std::string::npos);
}

TEST(FemSymmetric, ANonSymmetricMatrixIsRefusedNamingTheEntry) {
    Problem p = problem("hilbert");
    const Pattern full = p.csr.pattern();
    std::vector<double> a = p.csr.a;
    a[full.row_ptr[10] + 1] *= 1.5;  // row 10's second entry, its transpose left alone
    try {
        make_symmetric(full, a.data(), 1, 4096);
        FAIL() << "a non-symmetric matrix was accepted";
    } catch (const std::invalid_argument& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("not symmetric"), std::string::npos) << what;
        EXPECT_NE(what.find("--strategy=csr"), std::string::npos) << what;
    }
    // A difference below the 1e-14 relative allowance (round-off of a summation order) passes.
    std::vector<double> b = p.csr.a;
    b[full.row_ptr[10] + 1] *= 1 + 1e-16;
    EXPECT_NO_THROW(make_symmetric(full, b.data(), 1, 4096));
}

TEST(FemSymmetric, CgAndTheInverseIterationAgreeWithCsr) {
    Problem p = problem("hilbert");
    const Pattern full = p.csr.pattern();
    const std::size_t n = p.x.size();
    for (int threads : {1, 2}) {
        SCOPED_TRACE(std::to_string(threads) + " threads");
        const SymmetricMatrix sa = make_symmetric(full, p.csr.a.data(), threads, 64);
        const SymmetricMatrix sm = make_symmetric(full, p.csr.m.data(), threads, 64);
        std::vector<double> ones(n, 1.0), f(n);
        spmv_rows(full, p.csr.m.data(), ones.data(), f.data(), 0, full.n);
        auto solve = [&](const Operator& a, std::vector<double>& x) {
            std::vector<double> r(n), pp(n), q(n), partial(16 * static_cast<std::size_t>(threads));
            x.assign(n, 0.0);
            CgResult out;
#pragma omp parallel num_threads(threads)
            {
                TeamSum sum(partial.data());
                const CgResult res = cg_team(a, f.data(), x.data(), {r.data(), pp.data(), q.data()}, 1e-10, 100000, sum,
                                             my_block(full.n));
#pragma omp master
                out = res;
            }
            return out;
        };
        std::vector<double> x_csr, x_sym;
        const CgResult c = solve(Operator::of_csr(full, p.csr.a.data()), x_csr);
        const CgResult s = solve(Operator::of_symmetric(sa.pattern, sa.values()), x_sym);
        ASSERT_TRUE(c.converged && s.converged);
        EXPECT_NEAR(s.iterations, c.iterations, 2);
        std::string detail;
        EXPECT_EQ(check_cg_solution(full, p.csr.a.data(), f.data(), x_sym.data(), s, 1e-10, detail), "") << detail;

        auto eigen = [&](const Operator& a, const Operator& m) {
            std::vector<double> u(n), ff(n), au(n), mu(n), r(n), pp(n), q(n),
                partial(16 * static_cast<std::size_t>(threads));
            EigenResult out;
#pragma omp parallel num_threads(threads)
            {
                TeamSum sum(partial.data());
                const EigenResult res = inverse_iteration_team(
                    a, m, {u.data(), ff.data(), au.data(), mu.data(), {r.data(), pp.data(), q.data()}}, 1e-10, 1e-10,
                    100000, sum, my_block(full.n));
#pragma omp master
                out = res;
            }
            return out;
        };
        const EigenResult ec = eigen(Operator::of_csr(full, p.csr.a.data()), Operator::of_csr(full, p.csr.m.data()));
        const EigenResult es =
            eigen(Operator::of_symmetric(sa.pattern, sa.values()), Operator::of_symmetric(sm.pattern, sm.values()));
        ASSERT_TRUE(ec.converged && es.converged);
        EXPECT_NEAR(es.lambda, ec.lambda, 1e-9 * ec.lambda);
    }
}

}  // namespace
}  // namespace suite::fem
