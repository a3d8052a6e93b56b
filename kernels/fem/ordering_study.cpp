#include "kernels/fem/ordering_study.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "harness/common/stats.hpp"
#include "harness/kernel/arena.hpp"
#include "harness/kernel/blocks.hpp"
#include "kernels/fem/assembly.hpp"
#include "kernels/fem/csr.hpp"
#include "kernels/fem/fem_mesh.hpp"

namespace suite::fem {

namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

std::string fmt(const char* f, double v) {
    char b[64];
    std::snprintf(b, sizeof b, f, v);
    return b;
}

}  // namespace

const ChoiceTable<MatrixOrdering>& matrix_orderings() {
    static const ChoiceTable<MatrixOrdering> table = [] {
        using From = MatrixOrdering::From;
        std::vector<Choice<MatrixOrdering>> all;
        for (const auto& c : fem_orderings().all())
            all.push_back({c.name, c.help, {From::mesh, "mesh toolkit (kernels/sfc)"}});
        all.push_back(
            {"amd", "approximate minimum degree of A's graph, by SuiteSparse", {From::amd, "SuiteSparse AMD"}});
        all.push_back({"nd", "nested dissection of A's graph, by METIS", {From::nested_dissection, "METIS_NodeND"}});
        return ChoiceTable<MatrixOrdering>(fem_orderings().what(), std::move(all));
    }();
    return table;
}

void spmv(const Csr& b, const double* x, double* y, int threads) {
    const Pattern p{b.n, const_cast<std::uint32_t*>(b.row_ptr.data()), const_cast<std::uint32_t*>(b.col.data())};
#pragma omp parallel num_threads(threads)
    {
        const Block blk = my_block(b.n);
        spmv_rows(p, b.val.data(), x, y, blk.lo, blk.hi);
    }
}

std::uint64_t study_bytes(const mesh::MeshCounts& c) {
    const std::uint64_t nv = c.vertices, ne = c.elements,
                        nz = 2 * nv + 3 * ne;  // P1 triangles: nonzeros <= 2 nv + 3 ne
    const std::uint64_t mesh = 16 * nv + 12 * ne, matrix = 12 * nz + 4 * nv;
    return 3 * mesh + 6 * matrix + 32 * nv;
}

MatrixUnderStudy prepare_matrix(const mesh::Mesh& m, double delta) {
    const MeshArrays arrays{static_cast<std::int64_t>(m.vertices()), static_cast<std::int64_t>(m.elements()),
                            m.x.data(), m.y.data(), m.conn.data()};
    AssembledCsr assembled = assemble_reference(arrays, delta);
    MatrixUnderStudy s;
    Csr& a = s.a;
    a.n = arrays.nv;
    a.row_ptr = std::move(assembled.row_ptr);
    a.col = std::move(assembled.col);
    a.val = std::move(assembled.a);
    s.asymmetry = symmetrize_from_lower(a);
    if (!(s.asymmetry <= 1e-12))
        throw std::runtime_error("the assembled A is not symmetric: entries differ from their twins by " +
                                 fmt("%.3g", s.asymmetry));
    check_definite(a);
    s.x.resize(static_cast<std::size_t>(a.n));
    s.y_ref.resize(s.x.size());
    for (std::int64_t i = 0; i < a.n; ++i)
        s.x[static_cast<std::size_t>(i)] = 1.0 + 0.5 * std::sin(0.37 * static_cast<double>(i));
    spmv(a, s.x.data(), s.y_ref.data(), 1);
    return s;
}

OrderingStudy study_ordering(const MatrixUnderStudy& mat, const mesh::Mesh& m, const std::string& name,
                             const StudySettings& set) {
    const Csr& a = mat.a;
    OrderingStudy r;
    const MatrixOrdering& how = matrix_orderings().at(name).what;
    r.name = name;
    r.source = how.source;
    const auto t0 = Clock::now();
    const std::vector<std::uint32_t> perm = how.from == MatrixOrdering::From::amd ? amd_order(a)
                                            : how.from == MatrixOrdering::From::nested_dissection
                                                ? nested_dissection_order(a)
                                                : mesh_vertex_order(m, name, set.seed);
    r.order_s = since(t0);
    if (!is_permutation(perm, static_cast<std::size_t>(a.n)))
        throw std::runtime_error(name + ": the ordering is not a permutation of the rows");
    r.permuted = permute_symmetric(a, perm);
    const Csr& b = r.permuted;
    r.structure = structure(b);

    // The factor: analysed first; computed when it fits under the limit.
    r.symbolic = analyse(b);
    r.factor_bytes = 12.0 * r.symbolic.factor_nnz;
    // CHOLMOD's supernodal factor and its workspace: about twice the values and indices.
    r.memory_available = static_cast<double>(available_memory_bytes(MemoryPolicy{}));
    r.factor_over_memory = r.factor_bytes <= set.max_factor_bytes && 2 * r.factor_bytes > r.memory_available;
    if (r.factor_bytes <= set.max_factor_bytes && !r.factor_over_memory) {
        r.factor = factorise(b, set.reps);
        if (!(r.factor.residual < 1e-8 && r.factor.max_error < 1e-6))
            throw std::runtime_error(name + ": the Cholesky solve did not reproduce x = 1 (residual " +
                                     fmt("%.3g", r.factor.residual) + ", max error " + fmt("%.3g", r.factor.max_error) +
                                     ")");
        r.factorised = true;
        r.factor_median_s = summarise(r.factor.factor_seconds).median;
        r.solve_median_s = summarise(r.factor.solve_seconds).median;
    }

    // SpMV on the permuted matrix: x permuted alike, so y must be y_ref permuted.
    std::vector<double> xb(mat.x.size()), yb(mat.x.size());
    for (std::int64_t i = 0; i < a.n; ++i) xb[static_cast<std::size_t>(i)] = mat.x[perm[static_cast<std::size_t>(i)]];
    spmv(b, xb.data(), yb.data(), set.threads);  // warm-up
    for (int k = 0; k < set.reps; ++k) {
        const auto s0 = Clock::now();
        spmv(b, xb.data(), yb.data(), set.threads);
        r.spmv_seconds.push_back(since(s0));
    }
    double worst = 0;
    for (std::int64_t i = 0; i < a.n; ++i) {
        double scale = 0;
        for (std::uint32_t k = a.row_ptr[perm[i]]; k < a.row_ptr[perm[i] + 1]; ++k)
            scale += std::fabs(a.val[k] * mat.x[a.col[k]]);
        worst =
            std::max(worst, std::fabs(yb[static_cast<std::size_t>(i)] - mat.y_ref[perm[i]]) / (scale > 0 ? scale : 1));
    }
    if (!(worst <= 1e-12))
        throw std::runtime_error(name + ": the SpMV of the permuted matrix differs from the unpermuted one by " +
                                 fmt("%.3g", worst));
    r.spmv_max_error = worst;
    r.spmv_median_s = summarise(r.spmv_seconds).median;
    r.spmv_bytes =
        12.0 * static_cast<double>(a.nnz()) + 4.0 * static_cast<double>(a.n + 1) + 16.0 * static_cast<double>(a.n);
    r.spy = spy_grid(b, set.spy_bins, &r.spy_bins);
    return r;
}

}  // namespace suite::fem
