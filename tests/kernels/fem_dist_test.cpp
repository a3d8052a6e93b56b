// The distributed finite element kernels (kernels/fem/partition, distributed, fem_dist) on 1 to 4
// ranks made of threads (thread_comm.hpp): partitions that cover every row once, partition quality
// on a case small enough to check by hand, the distributed product equal to the serial one to the
// bit, CG in the serial iteration count, λ equal to the serial inverse iteration's, and the
// registered kernels set up, run and verified on two ranks.
#include <omp.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "harness/common/units.hpp"
#include "harness/kernel/blocks.hpp"
#include "harness/kernel/kernel.hpp"
#include "kernels/fem/assembly.hpp"
#include "kernels/fem/distributed.hpp"
#include "kernels/fem/fem_mesh.hpp"
#include "kernels/fem/partition.hpp"
#include "kernels/fem/solver.hpp"
#include "tests/kernels/thread_comm.hpp"

namespace suite::fem {
namespace {

using testing_comm::run_ranks;

const std::string disk = "disk:refine=4";
const std::string circle = "file:" + std::string(SUITE_SOURCE_DIR) + "/../shared/meshes/unit_circle.txt";

// The global problem as every rank sets it up: the mesh in an ordering, A and M assembled serially.
struct Global {
    mesh::Mesh mesh;
    AssembledCsr csr;
    std::vector<double> x;  // a smooth field, as fem-spmv multiplies
    Pattern pattern() { return csr.pattern(); }
};
Global global_problem(const std::string& spec, const std::string& ordering) {
    Global g;
    g.mesh = load_fem_mesh(spec, ordering, 1);
    const std::int64_t nv = static_cast<std::int64_t>(g.mesh.vertices()),
                       ne = static_cast<std::int64_t>(g.mesh.elements());
    g.csr = assemble_reference({nv, ne, g.mesh.x.data(), g.mesh.y.data(), g.mesh.conn.data()}, 0.05);
    for (std::int64_t i = 0; i < nv; ++i)
        g.x.push_back(1.0 + 0.5 * g.mesh.x[static_cast<std::size_t>(i)] - 0.25 * g.mesh.y[static_cast<std::size_t>(i)]);
    return g;
}

// The tridiagonal pattern of the path 0 - 1 - ... - (n-1): small enough to count a partition's cost by hand.
struct Path {
    std::vector<std::uint32_t> row_ptr{0}, col;
    explicit Path(int n) {
        for (int i = 0; i < n; ++i) {
            for (int j = std::max(0, i - 1); j <= std::min(n - 1, i + 1); ++j)
                col.push_back(static_cast<std::uint32_t>(j));
            row_ptr.push_back(static_cast<std::uint32_t>(col.size()));
        }
    }
    Pattern pattern() { return {static_cast<std::int64_t>(row_ptr.size()) - 1, row_ptr.data(), col.data()}; }
};

// One rank's share, with the vectors sized for its halo.
struct Rank {
    LocalMatrix lm;
    DistributedSolver solver;
    Rank(const Comm& comm, Global& g, PartitionScheme s)
        : lm(local_matrix(g.pattern(), g.csr.a.data(), g.csr.m.data(), make_partition(s, g.pattern(), comm.size(), 1),
                          comm.rank())),
          solver(comm, {lm.pattern(), lm.a.data(), lm.m.data(), lm.halo}, HaloExchange(lm.owned, lm.links)) {}
    std::vector<double> vec(bool with_halo) const {
        return std::vector<double>(static_cast<std::size_t>(lm.owned + (with_halo ? lm.halo : 0)));
    }
};

int serial_cg_iterations(Global& g, std::vector<double>& f) {
    const std::size_t n = g.x.size();
    std::vector<double> ones(n, 1.0), x(n, 0.0), r(n), p(n), q(n), partial(16);
    f.assign(n, 0.0);
    spmv_rows(g.pattern(), g.csr.m.data(), ones.data(), f.data(), 0, static_cast<std::int64_t>(n));
    CgResult out;
#pragma omp parallel num_threads(1)
    {
        TeamSum sum(partial.data());
        out = cg_team(g.pattern(), g.csr.a.data(), f.data(), x.data(), {r.data(), p.data(), q.data()}, 1e-10, 100000,
                      sum, {0, static_cast<std::int64_t>(n)});
    }
    EXPECT_TRUE(out.converged);
    return out.iterations;
}

double serial_lambda(Global& g) {
    const std::size_t n = g.x.size();
    std::vector<double> u(n), f(n), au(n), mu(n), r(n), p(n), q(n), partial(16);
    EigenResult out;
#pragma omp parallel num_threads(1)
    {
        TeamSum sum(partial.data());
        out = inverse_iteration_team(g.pattern(), g.csr.a.data(), g.csr.m.data(),
                                     {u.data(), f.data(), au.data(), mu.data(), {r.data(), p.data(), q.data()}}, 1e-8,
                                     1e-10, 100000, sum, {0, static_cast<std::int64_t>(n)});
    }
    EXPECT_TRUE(out.converged && !out.cg_failed);
    return out.lambda;
}

TEST(FemDistPartition, CurveAndMetisCoverEveryRowOnce) {
    Global g = global_problem(disk, "hilbert");
    const Pattern p = g.pattern();
    for (PartitionScheme s : {PartitionScheme::curve, PartitionScheme::metis})
        for (int parts = 1; parts <= 4; ++parts) {
            const std::string what = std::string(partition_scheme_name(s)) + " parts=" + std::to_string(parts);
            const Partition part = make_partition(s, p, parts, 1);
            ASSERT_EQ(part.offsets.size(), static_cast<std::size_t>(parts) + 1) << what;
            EXPECT_EQ(part.offsets.front(), 0) << what;
            EXPECT_EQ(part.offsets.back(), p.n) << what;
            std::vector<int> seen(static_cast<std::size_t>(p.n), 0);
            for (int q = 0; q < parts; ++q) {
                EXPECT_GT(part.rows_of(q), 0) << what << " part " << q;
                for (std::int64_t at = part.offsets[static_cast<std::size_t>(q)];
                     at < part.offsets[static_cast<std::size_t>(q) + 1]; ++at) {
                    const std::uint32_t row = part.order[static_cast<std::size_t>(at)];
                    ++seen[row];
                    EXPECT_EQ(part.part_of[row], q) << what << " row " << row;
                    // Rows keep their relative order inside a part; the curve keeps the numbering itself.
                    if (at > part.offsets[static_cast<std::size_t>(q)]) {
                        EXPECT_LT(part.order[static_cast<std::size_t>(at) - 1], row) << what;
                    }
                    if (s == PartitionScheme::curve) {
                        EXPECT_EQ(row, at) << what;
                    }
                }
            }
            EXPECT_TRUE(std::all_of(seen.begin(), seen.end(), [](int c) { return c == 1; })) << what;
            // Both balance nonzeros: the curve to a row (about 7 entries), METIS to its 3 % tolerance.
            const PartitionQuality qual = partition_quality(p, part);
            EXPECT_EQ(std::accumulate(qual.nnz.begin(), qual.nnz.end(), std::int64_t{0}),
                      static_cast<std::int64_t>(p.nnz()))
                << what;
            EXPECT_LT(qual.imbalance_nnz, s == PartitionScheme::curve ? 1.02 : 1.06) << what;
            if (parts == 1) {
                EXPECT_EQ(qual.edge_cut, 0) << what;
            }
            // Every rank's local matrix holds its rows and nothing else.
            std::int64_t owned = 0;
            for (int q = 0; q < parts; ++q) owned += local_matrix(p, nullptr, nullptr, part, q).owned;
            EXPECT_EQ(owned, p.n) << what;
        }
}

TEST(FemDistPartition, QualityOfAPathCountedByHand) {
    Path path(6);  // rows of 2, 3, 3, 3, 3, 2 entries: 16
    const Pattern p = path.pattern();
    // The curve in three: 16/3 nonzeros a part puts the cuts after rows 1 and 3.
    const Partition three = curve_partition(p, 3);
    EXPECT_EQ(three.offsets, (std::vector<std::int64_t>{0, 2, 4, 6}));
    const PartitionQuality q3 = partition_quality(p, three);
    EXPECT_EQ(q3.edge_cut, 2);                                 // 1-2 and 3-4
    EXPECT_EQ(q3.halo, (std::vector<std::int64_t>{1, 2, 1}));  // {2}, {1, 4}, {3}
    EXPECT_EQ(q3.neighbours, (std::vector<std::int64_t>{1, 2, 1}));
    EXPECT_EQ(q3.nnz, (std::vector<std::int64_t>{5, 6, 5}));
    EXPECT_DOUBLE_EQ(q3.imbalance_rows, 1.0);
    EXPECT_DOUBLE_EQ(q3.imbalance_nnz, 6.0 / (16.0 / 3.0));
    // Alternating parts {1, 3, 4} and {0, 2, 5}: four of the five edges cut, every row on a border.
    const Partition mixed = partition_from_parts(6, 2, {1, 0, 1, 0, 0, 1});
    EXPECT_EQ(mixed.order, (std::vector<std::uint32_t>{1, 3, 4, 0, 2, 5}));
    const PartitionQuality qm = partition_quality(p, mixed);
    EXPECT_EQ(qm.edge_cut, 4);
    EXPECT_EQ(qm.halo, (std::vector<std::int64_t>{3, 3}));
    EXPECT_EQ(qm.neighbours, (std::vector<std::int64_t>{1, 1}));
    EXPECT_DOUBLE_EQ(qm.imbalance_nnz, 9.0 / 8.0);
    // Part 0's local matrix: owned 1, 3, 4 -> 0, 1, 2; halo 0, 2, 5 -> 3, 4, 5 (part 1's order); each
    // row's entries in the global column order.
    const LocalMatrix lm = local_matrix(p, nullptr, nullptr, mixed, 0);
    EXPECT_EQ(lm.owned, 3);
    EXPECT_EQ(lm.halo, 3);
    EXPECT_EQ(lm.global, (std::vector<std::uint32_t>{1, 3, 4, 0, 2, 5}));
    EXPECT_EQ(lm.row_ptr, (std::vector<std::uint32_t>{0, 3, 6, 9}));
    EXPECT_EQ(lm.col, (std::vector<std::uint32_t>{3, 0, 4, 4, 1, 2, 1, 2, 5}));
    ASSERT_EQ(lm.links.size(), 1u);
    EXPECT_EQ(lm.links[0].rank, 1);
    EXPECT_EQ(lm.links[0].send, (std::vector<std::uint32_t>{0, 1, 2}));  // part 1 reads rows 1, 3, 4
    EXPECT_EQ(lm.links[0].recv_offset, 0);
    EXPECT_EQ(lm.links[0].recv_count, 3);
}

TEST(FemDistPartition, MetisIsThereOrNamedAsMissing) {
#if defined(SUITE_HAVE_SPARSE)
    EXPECT_NO_THROW(require_metis());
#else
    try {
        require_metis();
        ADD_FAILURE() << "a build without METIS must refuse --strategy=metis";
    } catch (const UsageError& e) {
        EXPECT_NE(std::string(e.what()).find("libmetis-dev"), std::string::npos) << e.what();
    }
#endif
    EXPECT_THROW(parse_partition_scheme("scotch"), UsageError);
}

TEST(FemDistSpmv, EqualsTheSerialProductBitForBit) {
    for (const char* ordering : {"hilbert", "random"}) {
        Global g = global_problem(disk, ordering);
        std::vector<double> y(g.x.size());
        spmv_rows(g.pattern(), g.csr.a.data(), g.x.data(), y.data(), 0, g.pattern().n);
        for (PartitionScheme s : {PartitionScheme::curve, PartitionScheme::metis})
            for (int ranks = 1; ranks <= 4; ++ranks) {
                std::vector<std::int64_t> mismatches(static_cast<std::size_t>(ranks), -1),
                    wrong_halo(static_cast<std::size_t>(ranks), -1);
                run_ranks(ranks, [&](const Comm& comm) {
                    omp_set_num_threads(1 + comm.rank() % 2);  // the team inside a rank must not matter either
                    Rank r(comm, g, s);
                    std::vector<double> x = r.vec(true), yd = r.vec(false);
                    for (std::int64_t i = 0; i < r.lm.owned; ++i)
                        x[static_cast<std::size_t>(i)] = g.x[r.lm.global[static_cast<std::size_t>(i)]];
                    r.solver.spmv(r.lm.a.data(), x.data(), yd.data());
                    std::int64_t bad = 0, halo = 0;
                    for (std::size_t i = 0; i < yd.size(); ++i) bad += yd[i] != y[r.lm.global[i]];
                    for (std::size_t i = yd.size(); i < x.size(); ++i) halo += x[i] != g.x[r.lm.global[i]];
                    mismatches[static_cast<std::size_t>(comm.rank())] = bad;
                    wrong_halo[static_cast<std::size_t>(comm.rank())] = halo;
                });
                for (int q = 0; q < ranks; ++q) {
                    EXPECT_EQ(mismatches[static_cast<std::size_t>(q)], 0)
                        << ordering << " " << partition_scheme_name(s) << " ranks=" << ranks << " rank " << q;
                    EXPECT_EQ(wrong_halo[static_cast<std::size_t>(q)], 0)
                        << ordering << " " << partition_scheme_name(s) << " ranks=" << ranks << " rank " << q;
                }
            }
    }
}

TEST(FemDistCg, ConvergesInTheSerialCountWithinOne) {
    Global g = global_problem(disk, "hilbert");
    std::vector<double> f;
    const int serial = serial_cg_iterations(g, f);
    for (PartitionScheme s : {PartitionScheme::curve, PartitionScheme::metis})
        for (int ranks = 1; ranks <= 4; ++ranks) {
            std::vector<int> its(static_cast<std::size_t>(ranks), -1);
            std::vector<double> residual(static_cast<std::size_t>(ranks), -1);
            run_ranks(ranks, [&](const Comm& comm) {
                omp_set_num_threads(1);
                Rank r(comm, g, s);
                std::vector<double> x = r.vec(true), fd = r.vec(false), rv = r.vec(false), p = r.vec(true),
                                    q = r.vec(false), ax = r.vec(false);
                for (std::int64_t i = 0; i < r.lm.owned; ++i)
                    fd[static_cast<std::size_t>(i)] = f[r.lm.global[static_cast<std::size_t>(i)]];
                const CgResult out = r.solver.cg(fd.data(), x.data(), {rv.data(), p.data(), q.data()}, 1e-10, 100000);
                // The true residual, by another distributed product.
                r.solver.spmv(r.lm.a.data(), x.data(), ax.data());
                std::array<double, 2> s2{0, 0};
                for (std::size_t i = 0; i < ax.size(); ++i)
                    s2[0] += (fd[i] - ax[i]) * (fd[i] - ax[i]), s2[1] += fd[i] * fd[i];
                comm.sum(s2);
                its[static_cast<std::size_t>(comm.rank())] = out.converged ? out.iterations : -1;
                residual[static_cast<std::size_t>(comm.rank())] = std::sqrt(s2[0] / s2[1]);
            });
            const std::string what = std::string(partition_scheme_name(s)) + " ranks=" + std::to_string(ranks);
            for (int q = 0; q < ranks; ++q) {
                EXPECT_EQ(its[static_cast<std::size_t>(q)], its[0]) << what << ": every rank takes the same decisions";
                EXPECT_LE(residual[static_cast<std::size_t>(q)], 1e-9) << what;
            }
            EXPECT_NEAR(its[0], serial, ranks == 1 ? 0 : 1) << what;
        }
}

TEST(FemDistEigen, LambdaEqualsTheSerialInverseIteration) {
    Global g = global_problem(circle, "hilbert");
    const double serial = serial_lambda(g);
    for (PartitionScheme s : {PartitionScheme::curve, PartitionScheme::metis})
        for (int ranks = 1; ranks <= 4; ++ranks) {
            if (s == PartitionScheme::metis && ranks != 3)
                continue;  // one METIS case: the curve's cover the rank counts
            std::vector<double> lambda(static_cast<std::size_t>(ranks), 0);
            run_ranks(ranks, [&](const Comm& comm) {
                omp_set_num_threads(1);
                Rank r(comm, g, s);
                std::vector<double> u = r.vec(true), f = r.vec(false), au = r.vec(false), mu = r.vec(false),
                                    rv = r.vec(false), p = r.vec(true), q = r.vec(false);
                const EigenResult e = r.solver.inverse_iteration(
                    {u.data(), f.data(), au.data(), mu.data(), {rv.data(), p.data(), q.data()}}, 1e-8, 1e-10, 100000);
                lambda[static_cast<std::size_t>(comm.rank())] =
                    e.converged && !e.cg_failed && e.residual < 1e-3 ? e.lambda : NAN;
            });
            for (int q = 0; q < ranks; ++q) {
                EXPECT_EQ(lambda[static_cast<std::size_t>(q)], lambda[0]) << "the ranks' λ must agree to the bit";
                EXPECT_LE(std::fabs(lambda[static_cast<std::size_t>(q)] - serial), 1e-7 * std::fabs(serial))
                    << partition_scheme_name(s) << " ranks=" << ranks << ": λ " << lambda[static_cast<std::size_t>(q)]
                    << ", serial " << serial;
            }
        }
}

TEST(FemDistPartition, TheHilbertCurveNeedsAFarSmallerHaloThanARandomOrder) {
    auto total_halo = [](const char* ordering) {
        Global g = global_problem(circle, ordering);
        const PartitionQuality q = partition_quality(g.pattern(), curve_partition(g.pattern(), 4));
        return std::accumulate(q.halo.begin(), q.halo.end(), std::int64_t{0});
    };
    const std::int64_t hilbert = total_halo("hilbert"), random = total_halo("random");
    EXPECT_GT(hilbert, 0);
    EXPECT_LT(5 * hilbert, random) << "halo of the curve's pieces: hilbert " << hilbert << ", random " << random;
}

// The registered kernels, set up, run and verified on two ranks as suite-mpi would run them.
TEST(FemDistKernel, EveryKernelVerifiesOnTwoRanksAndFailsBeforeItRan) {
    for (const char* name : {"fem-spmv-dist", "fem-cg-dist", "fem-eigen-dist"}) {
        const KernelEntry* k = find_kernel(name);
        ASSERT_NE(k, nullptr) << name;
        std::vector<int> before(2, -1), after(2, -1);
        std::vector<double> rows(2, 0), units(2, 0), ranks_fact(2, 0);
        run_ranks(2, [&](const Comm& comm) {
            omp_set_num_threads(1);
            KernelConfig cfg;
            cfg.access = {"hilbert", 0};
            cfg.variant = "curve";
            cfg.size = 1536;
            cfg.mesh = disk;
            cfg.params = default_params(k->info);
            cfg.comm = &comm;
            k->validate(cfg);
            Arena arena(MemoryPolicy{});
            auto kernel = k->make(cfg);
            kernel->setup(arena);
            const std::size_t me = static_cast<std::size_t>(comm.rank());
            before[me] = kernel->verify().passed;
            kernel->run(2);
            const Verification v = kernel->verify();
            after[me] = v.passed;
            EXPECT_TRUE(v.passed) << name << " rank " << me << ": " << v.detail;
            for (const Fact& f : kernel->facts()) {
                if (f.name == "rows") rows[me] = f.value;
                if (f.name == "ranks") ranks_fact[me] = f.value;
            }
            units[me] = kernel->work().units;
        });
        EXPECT_EQ(before, (std::vector<int>{0, 0})) << name;
        EXPECT_EQ(after, (std::vector<int>{1, 1})) << name;
        EXPECT_EQ(ranks_fact, (std::vector<double>{2, 2})) << name;
        const Global g = global_problem(disk, "hilbert");
        EXPECT_EQ(rows[0] + rows[1], static_cast<double>(g.mesh.vertices())) << name;
        if (std::string(name) == "fem-spmv-dist") {
            EXPECT_EQ(units[0] + units[1], static_cast<double>(g.csr.col.size())) << name;
        }
    }
}

}  // namespace
}  // namespace suite::fem
