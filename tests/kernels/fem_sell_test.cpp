// SELL-C-σ (kernels/fem/sell.hpp): the padding of a small matrix counted by hand, the product equal
// to CSR's on a real mesh in every ordering, team size and σ (to the bit on this build, and to
// the bit across repeats), on_row called once a row in row order, a bad σ refused, a wrong value
// caught by the check, and CG and the inverse iteration on it matching the CSR solvers.
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
#include "kernels/fem/sell.hpp"
#include "kernels/fem/solver.hpp"

namespace suite::fem {
namespace {

constexpr std::int64_t C = sell_c;
// A generated disk (217 vertices): no mesh file needed, so the test runs in any checkout.
const std::string circle = "disk:refine=3";

// A pattern with the given row lengths, row i's columns 0, 1, ..., len - 1; values 1 + i + j / 8.
struct Small {
    std::vector<std::uint32_t> row_ptr{0}, col;
    std::vector<double> val;
    Pattern pattern() { return {static_cast<std::int64_t>(row_ptr.size()) - 1, row_ptr.data(), col.data()}; }
};
Small small(const std::vector<std::uint32_t>& lengths) {
    Small s;
    for (std::size_t i = 0; i < lengths.size(); ++i) {
        for (std::uint32_t j = 0; j < lengths[i]; ++j) {
            s.col.push_back(j);
            s.val.push_back(1.0 + static_cast<double>(i) + j / 8.0);
        }
        s.row_ptr.push_back(static_cast<std::uint32_t>(s.col.size()));
    }
    return s;
}

// Whether a product contracts a*x + s into an FMA: -(1 + 2^-29) + (1 + 2^-30)² is 2^-60 fused, 0
// rounded first. Each loop is probed as compiled in this build: CSR's row, and SELL's chunk (below,
// through the product the solvers call). Where both fuse or neither does, SELL equals CSR to the bit.
Small fma_probe() {
    Small m = small({2, 1});  // row 0 the probe; row 1 makes the matrix square
    m.val = {-1.0, 1.0 + std::ldexp(1.0, -30), 1.0};
    return m;
}
const std::vector<double> fma_probe_x = {1.0 + std::ldexp(1.0, -29), 1.0 + std::ldexp(1.0, -30)};
bool csr_fuses() {
    Small m = fma_probe();
    std::vector<double> y(1);
    spmv_rows(m.pattern(), m.val.data(), fma_probe_x.data(), y.data(), 0, 1);
    return y[0] != 0.0;
}
bool sell_fuses();
bool bit_identical_here() { return csr_fuses() == sell_fuses(); }

// y = A x by a team through the solvers' Operator; on_row's calls counted and their order checked.
std::vector<double> team_product(const SellMatrix& s, const std::vector<double>& x, int threads) {
    std::vector<double> y(x.size(), std::nan(""));
    std::vector<int> seen(x.size(), 0), ordered(static_cast<std::size_t>(threads), 1);
    const Operator op = Operator::of_sell(s.pattern, s.val.data());
#pragma omp parallel num_threads(threads)
    {
        std::int64_t last = -1;
        const int t = omp_get_thread_num();
        op.apply(x.data(), y.data(), my_block(static_cast<std::int64_t>(x.size())), [&](std::int64_t i, double yi) {
            ++seen[static_cast<std::size_t>(i)];
            if (i <= last || !(yi == y[static_cast<std::size_t>(i)])) ordered[static_cast<std::size_t>(t)] = 0;
            last = i;
        });
    }
    for (std::size_t i = 0; i < x.size(); ++i) EXPECT_EQ(seen[i], 1) << "on_row must be called once for row " << i;
    for (int t = 0; t < threads; ++t)
        EXPECT_EQ(ordered[static_cast<std::size_t>(t)], 1) << "rows in order, thread " << t;
    return y;
}

bool sell_fuses() {
    Small m = fma_probe();
    return team_product(make_sell(m.pattern(), m.val.data(), 1, sell_c), fma_probe_x, 1)[0] != 0.0;
}

TEST(FemSell, PaddingOfASmallMatrixCountedByHand) {
    // 4C rows of lengths 5, 1, 5, 1, ...: a chunk of C consecutive rows holds both lengths.
    std::vector<std::uint32_t> lengths;
    for (std::int64_t i = 0; i < 4 * C; ++i) lengths.push_back(i % 2 ? 1 : 5);
    Small m = small(lengths);
    const Pattern p = m.pattern();
    ASSERT_EQ(p.nnz(), static_cast<std::uint64_t>(12 * C));
    // σ = C, the order kept: 4 chunks of width 5, 20 C entries stored, 8 C of them padding.
    const SellCounts keep = count_sell(p, 1, C);
    EXPECT_EQ(keep.chunks, 4);
    EXPECT_EQ(keep.stored, static_cast<std::uint64_t>(20 * C));
    EXPECT_EQ(keep.padding(), static_cast<std::uint64_t>(8 * C));
    // σ = 2 C or 4 C: the long rows sorted into chunks of their own, no padding.
    for (std::int64_t sigma : {2 * C, 4 * C}) {
        EXPECT_EQ(count_sell(p, 1, sigma).stored, static_cast<std::uint64_t>(12 * C)) << "σ " << sigma;
        EXPECT_EQ(count_sell(p, 2, sigma).padding(), 0u) << "σ " << sigma << ", 2 threads of 2 C rows";
    }
    // One more row (length 5): a chunk with one lane used, C - 1 empty lanes of width 5.
    lengths.push_back(5);
    Small m2 = small(lengths);
    const SellCounts last = count_sell(m2.pattern(), 1, C);
    EXPECT_EQ(last.chunks, 5);
    EXPECT_EQ(last.padding(), static_cast<std::uint64_t>(8 * C + 5 * (C - 1)));
    // The layout of the first chunk under σ = C: column-major, padding value 0 at the lane's own row.
    const SellMatrix s = make_sell(p, m.val.data(), 1, C);
    EXPECT_EQ(s.pattern.chunk_ptr[1], static_cast<std::uint64_t>(5 * C));
    EXPECT_EQ(s.row[1], 1u);
    EXPECT_EQ(s.val[0 * C + 1], m.val[p.row_ptr[1]]) << "row 1's one entry";
    EXPECT_EQ(s.val[1 * C + 1], 0.0);
    EXPECT_EQ(s.col[1 * C + 1], 1u) << "padding reads x of the lane's own row";
    EXPECT_EQ(s.val[3 * C + 0], m.val[p.row_ptr[0] + 3]) << "row 0's fourth entry";
    // The product equals CSR's on both.
    for (Small* mm : {&m, &m2}) {
        const Pattern q = mm->pattern();
        std::vector<double> x(static_cast<std::size_t>(q.n)), ref(x.size());
        for (std::size_t i = 0; i < x.size(); ++i) x[i] = 0.5 + 0.125 * static_cast<double>(i % 5);
        spmv_rows(q, mm->val.data(), x.data(), ref.data(), 0, q.n);
        for (std::int64_t sigma : {C, 2 * C, 4 * C, 64 * C}) {
            const std::vector<double> y = team_product(make_sell(q, mm->val.data(), 2, sigma), x, 2);
            for (std::size_t i = 0; i < y.size(); ++i) EXPECT_NEAR(y[i], ref[i], 1e-13 * std::fabs(ref[i]));
        }
    }
}

TEST(FemSell, SigmaMustBeAPositiveMultipleOfC) {
    Small m = small({3, 2, 1});
    for (std::int64_t sigma : {std::int64_t{0}, -C, C + 1, C / 2})
        EXPECT_THROW(count_sell(m.pattern(), 1, sigma), std::invalid_argument) << "σ " << sigma;
    EXPECT_NO_THROW(count_sell(m.pattern(), 1, 3 * C));
}

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

TEST(FemSell, ProductEqualsCsrOnEveryOrderingTeamAndSigma) {
    for (const char* ordering : {"natural", "random", "hilbert", "rcm"}) {
        Problem p = problem(ordering);
        const Pattern full = p.csr.pattern();
        std::vector<double> ref(p.x.size());
        spmv_rows(full, p.csr.a.data(), p.x.data(), ref.data(), 0, full.n);
        std::uint64_t padding_kept = 0;
        for (int threads : {1, 2, 3})
            for (std::int64_t sigma : {C, 4 * C, 16 * C, 1024 * C}) {
                SCOPED_TRACE(std::string(ordering) + ", " + std::to_string(threads) + " threads, σ " +
                             std::to_string(sigma));
                const SellMatrix s = make_sell(full, p.csr.a.data(), threads, sigma);
                EXPECT_EQ(s.pattern.counts.stored, s.pattern.counts.nnz + s.pattern.counts.padding());
                if (sigma == C) padding_kept = s.pattern.counts.padding();
                EXPECT_LE(s.pattern.counts.padding(), padding_kept) << "sorting never pads more than σ = C";
                const std::vector<double> y = team_product(s, p.x, threads);
                std::string detail;
                EXPECT_EQ(
                    check_sell_product(full, p.csr.a.data(), s.pattern, s.val.data(), p.x.data(), y.data(), detail),
                    "");
                // Each row's terms in CSR order, then padding zeros: where both loops round alike,
                // the same y to the bit (else the check's 1e-13 of Σ|a x| a row holds).
                if (bit_identical_here()) {
                    EXPECT_EQ(y, ref) << detail;
                    EXPECT_NE(detail.find("CSR product exactly"), std::string::npos) << detail;
                }
                EXPECT_EQ(team_product(s, p.x, threads), y) << "a repeat, to the bit";
            }
    }
}

TEST(FemSell, TheCheckCatchesARaceAndAWrongValue) {
    Problem p = problem("hilbert");
    const Pattern full = p.csr.pattern();
    SellMatrix s = make_sell(full, p.csr.a.data(), 2, 4 * C);
    std::vector<double> y = team_product(s, p.x, 2);
    std::string detail;
    ASSERT_EQ(check_sell_product(full, p.csr.a.data(), s.pattern, s.val.data(), p.x.data(), y.data(), detail), "");
    y[static_cast<std::size_t>(static_block(full.n, 1, 2).lo)] *= 1 + 1e-9;
    EXPECT_NE(check_sell_product(full, p.csr.a.data(), s.pattern, s.val.data(), p.x.data(), y.data(), detail)
                  .find("serial replay"),
              std::string::npos);
    s.val[0] *= 1.001;  // lane 0's first value: the replay agrees with the team, CSR does not
    const std::vector<double> y2 = team_product(s, p.x, 2);
    EXPECT_NE(
        check_sell_product(full, p.csr.a.data(), s.pattern, s.val.data(), p.x.data(), y2.data(), detail).find("CSR's"),
        std::string::npos);
}

TEST(FemSell, CgAndTheInverseIterationMatchCsr) {
    Problem p = problem("hilbert");
    const Pattern full = p.csr.pattern();
    const std::size_t n = p.x.size();
    for (int threads : {1, 2}) {
        SCOPED_TRACE(std::to_string(threads) + " threads");
        const SellMatrix sa = make_sell(full, p.csr.a.data(), threads, 16 * C);
        const SellMatrix sm = make_sell(full, p.csr.m.data(), threads, 16 * C);
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
        std::vector<double> x_csr, x_sell;
        const CgResult c = solve(Operator::of_csr(full, p.csr.a.data()), x_csr);
        const CgResult s = solve(Operator::of_sell(sa.pattern, sa.val.data()), x_sell);
        ASSERT_TRUE(c.converged && s.converged);
        // The same products and on_row's sums in the same order: the same iterates to the bit.
        if (bit_identical_here()) {
            EXPECT_EQ(s.iterations, c.iterations);
            EXPECT_EQ(x_sell, x_csr);
        }
        EXPECT_NEAR(s.iterations, c.iterations, 2);
        std::string detail;
        EXPECT_EQ(check_cg_solution(full, p.csr.a.data(), f.data(), x_sell.data(), s, 1e-10, detail), "") << detail;
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
            eigen(Operator::of_sell(sa.pattern, sa.val.data()), Operator::of_sell(sm.pattern, sm.val.data()));
        ASSERT_TRUE(ec.converged && es.converged);
        EXPECT_NEAR(es.lambda, ec.lambda, 1e-12 * ec.lambda);
    }
}

}  // namespace
}  // namespace suite::fem
