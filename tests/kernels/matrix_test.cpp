// `suite matrix`: the permutation and structure functions on matrices small enough to check by
// hand, the library orderings against the mesh toolkit's by fill, the factorisation's own check,
// and the command end to end: its files, a Matrix Market export read back by SciPy, and its
// bad inputs (one line, exit 2, nothing written).
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <filesystem>
#include <fstream>

#include "harness/common/units.hpp"
#include "kernels/fem/assembly.hpp"
#include "kernels/fem/fem_mesh.hpp"
#include "kernels/fem/matrix_study.hpp"
#include "kernels/fem/ordering_study.hpp"
#include "kernels/fem/sparse_libs.hpp"
#include "kernels/mesh/generate.hpp"
#include "tests/process.hpp"

using namespace suite::fem;
using namespace suite::test;

namespace {

// A 4x4 symmetric matrix with distinct entries, so that any misplaced one shows.
Csr small() {
    // [ 1  2  0  3 ]
    // [ 2  4  5  0 ]
    // [ 0  5  6  0 ]
    // [ 3  0  0  7 ]
    Csr a;
    a.n = 4;
    a.row_ptr = {0, 3, 6, 8, 10};
    a.col = {0, 1, 3, 0, 1, 2, 1, 2, 0, 3};
    a.val = {1, 2, 3, 2, 4, 5, 5, 6, 3, 7};
    return a;
}

double at(const Csr& a, std::uint32_t i, std::uint32_t j) {
    for (std::uint32_t k = a.row_ptr[i]; k < a.row_ptr[i + 1]; ++k)
        if (a.col[k] == j) return a.val[k];
    return 0;
}

Csr disk_matrix(int refine, double delta = 0.05) {
    const suite::mesh::Mesh m = suite::mesh::disk_mesh(refine);
    const MeshArrays arrays{static_cast<std::int64_t>(m.vertices()), static_cast<std::int64_t>(m.elements()),
                            m.x.data(), m.y.data(), m.conn.data()};
    AssembledCsr r = assemble_reference(arrays, delta);
    Csr a;
    a.n = arrays.nv;
    a.row_ptr = r.row_ptr;
    a.col = r.col;
    a.val = r.a;
    EXPECT_LT(symmetrize_from_lower(a), 1e-12);
    return a;
}

}  // namespace

TEST(MatrixStudy, SymmetricPermutationRenumbersRowsAndColumnsAlike) {
    const Csr a = small();
    const std::vector<std::uint32_t> perm = {2, 0, 3, 1};  // new 0 is old 2, ...
    ASSERT_TRUE(is_permutation(perm, 4));
    EXPECT_FALSE(is_permutation({0, 0, 1, 2}, 4));
    EXPECT_FALSE(is_permutation({0, 1, 2}, 4));
    const Csr b = permute_symmetric(a, perm);
    for (std::uint32_t i = 0; i < 4; ++i)
        for (std::uint32_t j = 0; j < 4; ++j) EXPECT_EQ(at(b, i, j), at(a, perm[i], perm[j])) << i << "," << j;
    for (std::int64_t i = 0; i < 4; ++i)
        EXPECT_TRUE(std::is_sorted(b.col.begin() + b.row_ptr[i], b.col.begin() + b.row_ptr[i + 1]));
    EXPECT_EQ(inverse_permutation(perm), (std::vector<std::uint32_t>{1, 3, 0, 2}));
}

TEST(MatrixStudy, BandwidthProfileSpyAndMatrixMarketOfAKnownMatrix) {
    const Csr a = small();
    const Structure s = structure(a);
    EXPECT_EQ(s.bandwidth, 3u);            // the (0,3) entry
    EXPECT_EQ(s.profile, 0u + 1 + 1 + 3);  // rows start at columns 0, 0, 1, 0
    int bins = 0;
    const auto grid = spy_grid(a, 2, &bins);
    ASSERT_EQ(bins, 2);
    EXPECT_EQ(grid, (std::vector<std::uint64_t>{4, 2, 2, 2}));  // rows 0-1 x cols 0-1 hold 1,2,2,4; ...
    const std::string mm = matrix_market(a, {"a test"});
    EXPECT_EQ(mm,
              "%%MatrixMarket matrix coordinate real symmetric\n% a test\n4 4 7\n1 1 1\n2 1 2\n2 2 4\n3 2 5\n3 3 6\n4 "
              "1 3\n4 4 7\n");
}

TEST(MatrixStudy, MeshOrderingsArePermutationsAndShrinkTheProfile) {
    const suite::mesh::Mesh m = suite::mesh::disk_mesh(5);
    const Csr a = disk_matrix(5);
    const std::uint64_t natural = structure(a).profile;
    for (const auto& c : fem_orderings().all()) {
        const auto perm = mesh_vertex_order(m, c.name, 1);
        ASSERT_TRUE(is_permutation(perm, m.vertices())) << c.name;
        const std::uint64_t profile = structure(permute_symmetric(a, perm)).profile;
        if (c.what.how == suite::sfc::Ordering::How::sorted) {
            EXPECT_LT(profile, natural / 4) << c.name;  // the generator's refinement order is far from local
        }
    }
    EXPECT_THROW(mesh_vertex_order(m, "amd", 1), suite::UsageError);
}

TEST(MatrixStudy, FillReducingOrderingsFromTheLibrariesBeatTheBandedOnes) {
    if (!sparse_libs_missing().empty()) GTEST_SKIP() << "built without " << sparse_libs_missing();
    const suite::mesh::Mesh m = suite::mesh::disk_mesh(6);
    const Csr a = disk_matrix(6);
    const double rcm = analyse(permute_symmetric(a, mesh_vertex_order(m, "rcm", 1))).factor_nnz;
    const auto amd = amd_order(a), nd = nested_dissection_order(a);
    ASSERT_TRUE(is_permutation(amd, a.n));
    ASSERT_TRUE(is_permutation(nd, a.n));
    const double fill_amd = analyse(permute_symmetric(a, amd)).factor_nnz,
                 fill_nd = analyse(permute_symmetric(a, nd)).factor_nnz;
    // On a 2D mesh minimum degree and nested dissection leave far less fill than a band: this is
    // also what tells METIS's two output arrays apart (the other one fills like a random order).
    EXPECT_LT(fill_amd, rcm / 2) << "amd " << fill_amd << " rcm " << rcm;
    EXPECT_LT(fill_nd, rcm / 2) << "nd " << fill_nd << " rcm " << rcm;
    const Factorisation f = factorise(permute_symmetric(a, nd), 2);
    EXPECT_EQ(f.factor_seconds.size(), 2u);
    EXPECT_LT(f.residual, 1e-10);
    EXPECT_LT(f.max_error, 1e-8);
    EXPECT_EQ(f.method, "supernodal LLᵀ");
    EXPECT_GE(f.factor_nnz, static_cast<double>((a.nnz() + a.n) / 2));  // L holds at least A's lower triangle
}

TEST(MatrixStudy, AnIndefiniteMatrixIsRefusedByTheFactorisation) {
    if (!sparse_libs_missing().empty()) GTEST_SKIP() << "built without " << sparse_libs_missing();
    const Csr a = disk_matrix(4, 10000);  // a deep well: the lowest eigenvalue is negative
    EXPECT_THROW(check_definite(a), NotDefinite);
    EXPECT_THROW(factorise(a, 1), NotDefinite);
    EXPECT_NO_THROW(check_definite(disk_matrix(4)));
}

TEST(MatrixCli, WritesTheTableFiguresAndExportsThatSciPyReadsBack) {
    if (!sparse_libs_missing().empty()) GTEST_SKIP() << "built without " << sparse_libs_missing();
    TempDir dir;
    const std::string out = dir.file("m");
    const Outcome r = run_suite({"matrix", "--mesh=disk:refine=4", "--export=mtx", "--reps=2", "--out=" + out}, 300);
    ASSERT_EQ(r.status, 0) << describe(r);
    const std::vector<std::string> names = matrix_orderings().names();
    for (const auto& name : names) {
        EXPECT_NE(r.out.find("\n" + name + " "), std::string::npos) << r.out;
        EXPECT_TRUE(std::filesystem::exists(out + "/" + name + ".mtx")) << name;
    }
    EXPECT_TRUE(std::filesystem::exists(out + "/matrix.md"));
    const nlohmann::json doc = nlohmann::json::parse(std::ifstream(out + "/matrix.json"));
    ASSERT_EQ(doc["orderings"].size(), names.size());
    for (const auto& o : doc["orderings"]) {
        EXPECT_EQ(o["cholesky"]["computed"], true) << o["ordering"];
        EXPECT_EQ(o["cholesky"]["verification"]["passed"], true);
        EXPECT_EQ(o["spmv"]["verification"]["passed"], true);
        std::uint64_t total = 0;
        for (const auto& c : o["spy"]["counts"]) total += c.get<std::uint64_t>();
        EXPECT_EQ(total, doc["nonzeros"].get<std::uint64_t>());
    }
    std::vector<std::string> check = {SUITE_PYTHON, std::string(SUITE_SOURCE_DIR) + "/tests/check_mtx.py", out};
    check.insert(check.end(), names.begin(), names.end());
    const Outcome py = run_program(check);
    if (py.status == 3) GTEST_SKIP() << py.out;
    EXPECT_EQ(py.status, 0) << describe(py);
}

TEST(MatrixCli, BadInputIsOneLineExitTwoAndNothingWritten) {
    TempDir dir;
    const std::string out = dir.file("m");
    // The exact line and exit status 2; the --out directory never created.
    auto refused = [&](const std::vector<std::string>& args, const std::string& line, bool with_out = true) {
        std::vector<std::string> a = {"matrix", "--mesh=disk:refine=3"};
        if (with_out) a.push_back("--out=" + out);
        a.insert(a.end(), args.begin(), args.end());
        const Outcome r = run_suite(a);
        EXPECT_EQ(r.status, 2) << describe(r);
        EXPECT_EQ(r.err, "suite: error: " + line + "\n") << describe(r);
        EXPECT_TRUE(r.out.empty()) << describe(r);
        EXPECT_FALSE(std::filesystem::exists(out)) << describe(r);
    };
    refused({"--ordering=hilbrt"},
            "unknown ordering 'hilbrt' (did you mean 'hilbert'?); accepted: " + matrix_orderings().accepted());
    refused({"--delta=-1"}, "--delta=-1: δ must be >= 0 (the waveguide's k² = (100 + δ) exp(-50 r²) - 100)");
    refused({"--export=csv"}, "--export=csv: the one export format is mtx (Matrix Market)");
    refused({"--export=mtx"}, "--export=mtx writes into the --out directory: give --out=DIR", false);
    if (sparse_libs_missing().empty())
        refused({"--delta=10000"},
                "--mesh=disk:refine=3 --delta=10000: A is not positive definite (CHOLMOD met a non-positive pivot), so "
                "it has no Cholesky "
                "factor; δ deepens the well, and at this one the lowest eigenvalue is negative: give a smaller δ (the "
                "default 0.05 gives 88.3)");
    else
        refused({}, "suite matrix needs " + sparse_libs_missing() +
                        ", which this build did not find; install (scripts/install-deps.sh does) and rebuild");
}
