#include "kernels/fem/matrix_study.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <stdexcept>

#include "harness/common/units.hpp"
#include "kernels/fem/fem_mesh.hpp"
#include "kernels/sfc/encode.hpp"
#include "kernels/sfc/pipeline.hpp"

namespace suite::fem {

bool is_permutation(const std::vector<std::uint32_t>& perm, std::size_t n) {
    if (perm.size() != n) return false;
    std::vector<char> seen(n, 0);
    for (std::uint32_t p : perm) {
        if (p >= n || seen[p]) return false;
        seen[p] = 1;
    }
    return true;
}

std::vector<std::uint32_t> inverse_permutation(const std::vector<std::uint32_t>& perm) {
    std::vector<std::uint32_t> inv(perm.size());
    for (std::size_t i = 0; i < perm.size(); ++i) inv[perm[i]] = static_cast<std::uint32_t>(i);
    return inv;
}

Csr permute_symmetric(const Csr& a, const std::vector<std::uint32_t>& perm) {
    const std::vector<std::uint32_t> inv = inverse_permutation(perm);
    Csr b;
    b.n = a.n;
    b.row_ptr.assign(static_cast<std::size_t>(a.n) + 1, 0);
    for (std::int64_t i = 0; i < a.n; ++i)
        b.row_ptr[i + 1] = b.row_ptr[i] + (a.row_ptr[perm[i] + 1] - a.row_ptr[perm[i]]);
    b.col.resize(a.nnz());
    b.val.resize(a.nnz());
    std::vector<std::pair<std::uint32_t, double>> row;
    for (std::int64_t i = 0; i < a.n; ++i) {
        row.clear();
        for (std::uint32_t k = a.row_ptr[perm[i]]; k < a.row_ptr[perm[i] + 1]; ++k)
            row.emplace_back(inv[a.col[k]], a.val[k]);
        std::sort(row.begin(), row.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
        for (std::size_t t = 0; t < row.size(); ++t) {
            b.col[b.row_ptr[i] + t] = row[t].first;
            b.val[b.row_ptr[i] + t] = row[t].second;
        }
    }
    return b;
}

double symmetrize_from_lower(Csr& a) {
    double worst = 0;
    for (std::int64_t i = 0; i < a.n; ++i)
        for (std::uint32_t k = a.row_ptr[i]; k < a.row_ptr[i + 1] && a.col[k] < i; ++k) {
            const std::uint32_t j = a.col[k];
            const auto first = a.col.begin() + a.row_ptr[j], last = a.col.begin() + a.row_ptr[j + 1];
            const auto at = std::lower_bound(first, last, static_cast<std::uint32_t>(i));
            if (at == last || *at != i) throw std::logic_error("symmetrize_from_lower: the pattern is not symmetric");
            double& twin = a.val[static_cast<std::size_t>(at - a.col.begin())];
            const double scale = std::max(std::fabs(a.val[k]), std::fabs(twin));
            if (scale > 0) worst = std::max(worst, std::fabs(twin - a.val[k]) / scale);
            twin = a.val[k];
        }
    return worst;
}

Structure structure(const Csr& a) {
    Structure s;
    for (std::int64_t i = 0; i < a.n; ++i) {
        if (a.row_ptr[i] == a.row_ptr[i + 1]) continue;
        const std::int64_t first = a.col[a.row_ptr[i]], last = a.col[a.row_ptr[i + 1] - 1];
        s.bandwidth = std::max<std::uint64_t>(s.bandwidth, static_cast<std::uint64_t>(std::max(i - first, last - i)));
        if (first < i) s.profile += static_cast<std::uint64_t>(i - first);
    }
    return s;
}

std::vector<std::uint64_t> spy_grid(const Csr& a, int max_bins, int* bins) {
    const std::int64_t b = std::max<std::int64_t>(1, std::min<std::int64_t>(a.n, max_bins));
    *bins = static_cast<int>(b);
    std::vector<std::uint64_t> grid(static_cast<std::size_t>(b * b), 0);
    // Row i falls in bin floor(i b / n): every bin covers n/b rows, give or take one.
    for (std::int64_t i = 0; i < a.n; ++i) {
        const std::int64_t r = i * b / a.n;
        for (std::uint32_t k = a.row_ptr[i]; k < a.row_ptr[i + 1]; ++k)
            ++grid[static_cast<std::size_t>(r * b + static_cast<std::int64_t>(a.col[k]) * b / a.n)];
    }
    return grid;
}

std::string matrix_market(const Csr& a, const std::vector<std::string>& comments) {
    std::uint64_t lower = 0;
    for (std::int64_t i = 0; i < a.n; ++i)
        for (std::uint32_t k = a.row_ptr[i]; k < a.row_ptr[i + 1] && a.col[k] <= i; ++k) ++lower;
    std::string s = "%%MatrixMarket matrix coordinate real symmetric\n";
    for (const auto& c : comments) s += "% " + c + "\n";
    s += std::to_string(a.n) + " " + std::to_string(a.n) + " " + std::to_string(lower) + "\n";
    s.reserve(s.size() + lower * 40);
    char line[96];
    for (std::int64_t i = 0; i < a.n; ++i)
        for (std::uint32_t k = a.row_ptr[i]; k < a.row_ptr[i + 1] && a.col[k] <= i; ++k) {
            // %.17g: every double read back exactly.
            const int len = std::snprintf(line, sizeof line, "%lld %u %.17g\n", static_cast<long long>(i + 1),
                                          a.col[k] + 1, a.val[k]);
            s.append(line, static_cast<std::size_t>(len));
        }
    return s;
}

std::vector<std::uint32_t> mesh_vertex_order(const mesh::Mesh& m, const std::string& name, std::uint64_t seed) {
    const sfc::Ordering& o = fem_orderings().at(name).what;
    switch (o.how) {
        case sfc::Ordering::How::as_given: {
            std::vector<std::uint32_t> id(m.vertices());
            std::iota(id.begin(), id.end(), 0u);
            return id;
        }
        case sfc::Ordering::How::shuffled:
            return inverse_permutation(sfc::shuffled(m, seed).new_id);
        case sfc::Ordering::How::sorted:
            break;
    }
    return inverse_permutation(sfc::reorder(m, o.method, sfc::max_depth(m.dim)).new_id);
}

}  // namespace suite::fem
