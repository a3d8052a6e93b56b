// SELL-C-σ: counting, filling and checking (sell.hpp has the layout and the product).
#include "kernels/fem/sell.hpp"

#include <cmath>
#include <stdexcept>

#include "harness/common/units.hpp"

namespace suite::fem {

namespace {

std::uint32_t sell_row_length(const Pattern& p, std::int64_t i) { return p.row_ptr[i + 1] - p.row_ptr[i]; }

// The rows [lo, hi) of one window in the order their lanes take: by descending length, stable.
void sell_window_order(const Pattern& p, std::int64_t lo, std::int64_t hi, std::int64_t sigma,
                       std::vector<std::uint32_t>& order) {
    order.clear();
    for (std::int64_t i = lo; i < hi; ++i) order.push_back(static_cast<std::uint32_t>(i));
    if (sigma > sell_c)
        std::stable_sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) {
            return sell_row_length(p, a) > sell_row_length(p, b);
        });
}

// Calls chunk(first lane's index into order, lanes used, width) for each chunk of thread t, in order.
template <class Chunk>
void sell_walk_chunks(const Pattern& p, std::int64_t sigma, Block b, std::vector<std::uint32_t>& order, Chunk&& chunk) {
    for (std::int64_t lo = b.lo; lo < b.hi; lo += sigma) {
        const std::int64_t hi = std::min(lo + sigma, b.hi), m = hi - lo;
        sell_window_order(p, lo, hi, sigma, order);
        for (std::int64_t c0 = 0; c0 < m; c0 += sell_c) {
            const std::int64_t used = std::min<std::int64_t>(sell_c, m - c0);
            std::uint32_t width = 0;
            for (std::int64_t r = 0; r < used; ++r)
                width = std::max(width, sell_row_length(p, order[static_cast<std::size_t>(c0 + r)]));
            chunk(c0, used, static_cast<std::int64_t>(width));
        }
    }
}

}  // namespace

SellCounts count_sell(const Pattern& p, int threads, std::int64_t sigma) {
    if (!(sigma > 0 && sigma % sell_c == 0))
        throw std::invalid_argument("σ = " + std::to_string(sigma) +
                                    " is not a positive multiple of C = " + std::to_string(sell_c));
    if (p.n >= (std::int64_t{1} << 31))
        throw std::invalid_argument(
            "SELL-C-σ takes fewer than 2^31 rows (its row and column indices are 32-bit, with room for the padding)");
    SellCounts c;
    c.n = p.n;
    c.threads = threads;
    c.sigma = sigma;
    c.nnz = p.nnz();
    c.first_chunk.push_back(0);
    c.first_entry.push_back(0);
    std::vector<std::uint32_t> order;
    for (int t = 0; t < threads; ++t) {
        sell_walk_chunks(p, sigma, static_block(p.n, t, threads), order,
                         [&](std::int64_t, std::int64_t, std::int64_t w) {
                             ++c.chunks;
                             c.stored += static_cast<std::uint64_t>(w * sell_c);
                         });
        c.first_chunk.push_back(c.chunks);
        c.first_entry.push_back(c.stored);
    }
    return c;
}

void fill_sell(const Pattern& p, SellPattern& s) {
    const SellCounts& c = s.counts;
    const std::uint32_t none = static_cast<std::uint32_t>(c.n);
#pragma omp parallel num_threads(c.threads)
    {
        const int t = omp_get_thread_num();
        std::int64_t k = c.first_chunk[static_cast<std::size_t>(t)];
        std::uint64_t at = c.first_entry[static_cast<std::size_t>(t)];
        std::vector<std::uint32_t> order;
        sell_walk_chunks(p, c.sigma, static_block(c.n, t, c.threads), order,
                         [&](std::int64_t c0, std::int64_t used, std::int64_t width) {
                             s.chunk_ptr[k] = at;
                             for (std::int64_t r = 0; r < sell_c; ++r) {
                                 const std::uint32_t i = order[static_cast<std::size_t>(c0 + (r < used ? r : 0))];
                                 s.row[sell_c * k + r] = r < used ? i : none;
                                 const std::int64_t len = r < used ? sell_row_length(p, i) : 0;
                                 for (std::int64_t j = 0; j < width; ++j)
                                     s.col[at + static_cast<std::uint64_t>(sell_c * j + r)] =
                                         j < len ? p.col[p.row_ptr[i] + static_cast<std::uint32_t>(j)] : i;
                             }
                             at += static_cast<std::uint64_t>(sell_c * width);
                             ++k;
                         });
    }
    s.chunk_ptr[c.chunks] = c.stored;
}

void fill_sell_values(const Pattern& p, const double* csr_values, const SellPattern& s, double* val) {
    const SellCounts& c = s.counts;
#pragma omp parallel num_threads(c.threads)
    {
        const int t = omp_get_thread_num();
        for (std::int64_t k = c.first_chunk[static_cast<std::size_t>(t)]; k < c.first_chunk[t + 1u]; ++k) {
            const std::uint64_t at = s.chunk_ptr[k];
            const std::int64_t width = static_cast<std::int64_t>((s.chunk_ptr[k + 1] - at) / sell_c);
            for (std::int64_t r = 0; r < sell_c; ++r) {
                const std::uint32_t i = s.row[sell_c * k + r];
                const std::int64_t len = i < c.n ? sell_row_length(p, i) : 0;
                for (std::int64_t j = 0; j < width; ++j)
                    val[at + static_cast<std::uint64_t>(sell_c * j + r)] =
                        j < len ? csr_values[p.row_ptr[i] + static_cast<std::uint32_t>(j)] : 0.0;
            }
        }
    }
}

void sell_product_replay(const SellPattern& s, const double* val, const double* x, double* y) {
    for (int t = 0; t < s.counts.threads; ++t)
        sell_rows(s, val, x, y, t, static_block(s.counts.n, t, s.counts.threads), [](std::int64_t, double) {});
}

std::string check_sell_product(const Pattern& p, const double* a, const SellPattern& s, const double* val,
                               const double* x, const double* y, std::string& detail) {
    const std::int64_t n = p.n;
    std::vector<double> replay(static_cast<std::size_t>(n)), ref(static_cast<std::size_t>(n));
    sell_product_replay(s, val, x, replay.data());
    spmv_rows(p, a, x, ref.data(), 0, n);
    std::int64_t exact = 0;
    double worst = 0;
    for (std::int64_t i = 0; i < n; ++i) {
        const auto u = static_cast<std::size_t>(i);
        if (!(y[i] == replay[u]))
            return "y[" + std::to_string(i) + "] = " + format_number(y[i]) + ", its serial replay " +
                   format_number(replay[u]);
        double scale = 0;
        for (std::uint32_t k = p.row_ptr[i]; k < p.row_ptr[i + 1]; ++k) scale += std::fabs(a[k] * x[p.col[k]]);
        const double diff = std::fabs(y[i] - ref[u]);
        exact += y[i] == ref[u];
        if (!(diff <= 1e-13 * scale))
            return "y[" + std::to_string(i) + "] = " + format_number(y[i]) + ", CSR's " + format_number(ref[u]);
        if (scale > 0) worst = std::max(worst, diff / scale);
    }
    detail = "the SELL-C-σ y = A x (C = " + std::to_string(sell_c) + ", σ = " + std::to_string(s.counts.sigma) +
             ") equals a serial replay exactly and the CSR product " +
             (exact == n ? std::string("exactly")
                         : "to " + format_number(worst) + " of Σ|a x| a row (" + std::to_string(exact) + " of " +
                               std::to_string(n) + " rows to the bit)");
    return "";
}

SellMatrix make_sell(const Pattern& p, const double* values, int threads, std::int64_t sigma) {
    SellMatrix m;
    m.pattern.counts = count_sell(p, threads, sigma);
    const SellCounts& c = m.pattern.counts;
    m.chunk_ptr.resize(static_cast<std::size_t>(c.chunks + 1));
    m.row.resize(static_cast<std::size_t>(c.chunks * sell_c) + 1);
    m.col.resize(c.stored + 1);
    m.val.resize(c.stored + 1);
    m.pattern.chunk_ptr = m.chunk_ptr.data();
    m.pattern.row = m.row.data();
    m.pattern.col = m.col.data();
    fill_sell(p, m.pattern);
    fill_sell_values(p, values, m.pattern, m.val.data());
    return m;
}

}  // namespace suite::fem
