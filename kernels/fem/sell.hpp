#pragma once
// SELL-C-σ storage of a P1 matrix (Kreutzer, Hager, Wellein, Fehske, Bishop 2014) and its product
// y = A x over the team: the same y as the CSR product, with one vector instruction doing the work
// of C rows. The promise: each row's terms are added in its CSR order (then padding zeros), so y
// equals CSR's to the bit where both loops round alike, and to round-off where they do not.
//
// The layout. Each thread keeps its contiguous rows (static_block, the split of first touch) and
// cuts them into windows of σ rows from its first row. Within a window the rows are sorted by
// descending length (stable; σ = C keeps the order, as sorting inside a chunk saves nothing), and
// cut into chunks of C rows (the window's last chunk may hold fewer: empty lanes). A chunk is
// padded to its longest row and stored column-major: entry j of lane r at chunk_ptr + C j + r.
// Padding: value 0, column the lane's own row (x_i is read anyway) or, in an empty lane, the
// chunk's first row. Rows of like length share a chunk as σ grows, so the padding shrinks; the
// rows a chunk writes then lie further apart in y.
//   for chunk k: s[0..C) = 0; for j < width_k: s[r] += val[C j + r] * x[col[C j + r]]; y[row[C k + r]] = s[r]
#include <omp.h>

#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

#include "harness/kernel/blocks.hpp"
#include "kernels/fem/csr.hpp"
#include "kernels/fem/sell_arch.hpp"

namespace suite::fem {

// σ where --sell-sigma is not given: 64 C, the best of C, 16 C, 64 C, 256 C and 1024 C on this VM
// (docs/kernels.md), though by little and within the noise: the padding is below 1 % at every σ.
constexpr std::int64_t sell_default_sigma = 64 * sell_c;

// The shape of the storage for a team of `threads`: counted before allocating.
struct SellCounts {
    std::int64_t n = 0;
    int threads = 1;
    std::int64_t sigma = sell_c;
    std::int64_t chunks = 0;
    std::uint64_t nnz = 0;                   // of the CSR pattern
    std::uint64_t stored = 0;                // entries stored, padding included: C times the chunks' widths
    std::vector<std::int64_t> first_chunk;   // threads + 1: thread t's chunks [first_chunk[t], first_chunk[t + 1])
    std::vector<std::uint64_t> first_entry;  // threads + 1: thread t's first stored entry
    std::uint64_t padding() const { return stored - nnz; }
    // Bytes a product reads of the structure: every stored value and column, the chunk pointers and
    // the lanes' rows.
    double matrix_bytes() const {
        return 12.0 * static_cast<double>(stored) + 8.0 * static_cast<double>(chunks + 1) +
               4.0 * static_cast<double>(chunks * sell_c);
    }
};

// Counts windows, chunks and padding; throws std::invalid_argument when σ is not a positive
// multiple of C or the matrix has 2^31 rows or more (32-bit indices, with room for the padding).
SellCounts count_sell(const Pattern& p, int threads, std::int64_t sigma);

// The structure, on arrays the caller allocates from the counts.
struct SellPattern {
    SellCounts counts;
    std::uint64_t* chunk_ptr = nullptr;  // chunks + 1: chunk k's first entry (a multiple of C)
    std::uint32_t* row = nullptr;        // chunks * C: lane r of chunk k computes row row[C k + r] (empty: n)
    std::uint32_t* col = nullptr;        // stored
};

// Fills the structure (each thread its own chunks: the first touch of the product's split).
void fill_sell(const Pattern& p, SellPattern& s);
// One matrix's values in the structure (padding 0), each thread its own chunks.
void fill_sell_values(const Pattern& p, const double* csr_values, const SellPattern& s, double* val);

// Thread t's rows (its block b): y_i for each, then on_row(i, y_i) in row order once a window is
// done, so that a reduction fused into on_row adds in the order it does on CSR. No barrier.
template <class OnRow>
inline void sell_rows(const SellPattern& s, const double* val, const double* x, double* y, int t, Block b,
                      OnRow&& on_row) {
    const std::int64_t sigma = s.counts.sigma;
    std::int64_t k = s.counts.first_chunk[static_cast<std::size_t>(t)];
    for (std::int64_t lo = b.lo; lo < b.hi; lo += sigma) {
        const std::int64_t hi = std::min(lo + sigma, b.hi);
        for (std::int64_t first = lo; first < hi; first += sell_c, ++k) {
            alignas(64) double sums[sell_c];
            const std::uint64_t at = s.chunk_ptr[k];
            sell_chunk(val + at, s.col + at, static_cast<std::int64_t>((s.chunk_ptr[k + 1] - at) / sell_c), x, sums);
            const std::uint32_t* lanes = s.row + sell_c * k;
            const std::int64_t used = std::min<std::int64_t>(sell_c, hi - first);
            for (std::int64_t r = 0; r < used; ++r) y[lanes[r]] = sums[r];
        }
        for (std::int64_t i = lo; i < hi; ++i) on_row(i, y[i]);
    }
}

// y = A x by the whole team (of counts.threads threads); x whole before. No barrier.
template <class OnRow>
inline void sell_product_team(const SellPattern& s, const double* val, const double* x, double* y, OnRow&& on_row) {
    const int t = omp_get_thread_num();
    sell_rows(s, val, x, y, t, static_block(s.counts.n, t, s.counts.threads), on_row);
}

// The same product on one thread, thread block by thread block: every y_i the team computes.
void sell_product_replay(const SellPattern& s, const double* val, const double* x, double* y);

// y from the team against its serial replay (to the bit) and the CSR product: "" or what is wrong;
// detail says how close it came to CSR (the rows equal to the bit, the largest difference).
std::string check_sell_product(const Pattern& p, const double* a, const SellPattern& s, const double* val,
                               const double* x, const double* y, std::string& detail);

// Owns its arrays: for tests and tools (the kernels allocate from their arena).
struct SellMatrix {
    SellPattern pattern;
    std::vector<std::uint64_t> chunk_ptr;
    std::vector<std::uint32_t> row, col;
    std::vector<double> val;
};
SellMatrix make_sell(const Pattern& p, const double* values, int threads, std::int64_t sigma);

}  // namespace suite::fem
