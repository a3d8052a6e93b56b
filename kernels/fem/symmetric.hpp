#pragma once
// Symmetric storage of the P1 matrices and its race-free product y = A x over the team: a product
// that reads about half the matrix CSR reads. The promise: the same y as the CSR product to
// round-off, with no synchronised update inside a thread's rows and two barriers a product.
//
// The window scheme. Row i keeps its diagonal and its first K entries a_ij with i < j < i + W
// ("near"; W a power of two, K slots a row, padded with zeros) and, in both rows, every other
// entry ("far", plain CSR: |i - j| >= W, or past a row's K slots). Row i's product:
//   y_i = Σ_near a_ij x_j + Σ_far a_ij x_j + acc[i mod W]       (the gather, as CSR)
//   acc[j mod W] += a_ij x_i  for the near j > i                 (the transposed half)
// acc is a thread's ring of W doubles: the contributions of earlier rows to rows not reached yet.
// A row writes only ring slots of the next W - 1 rows, so y_i is final when row i is reached,
// without a zeroing pass over y. Along a space-filling curve, a vertex's neighbours are mostly a
// few hundred rows away: almost every entry is near, and stored once. The fixed K (chosen so that
// 95 % of rows fit) gives every row the same loop: with a row's own count of upper entries (0 to 5
// along Hilbert's curve) the loop's exit was mispredicted 0.8 times a row (callgrind), which
// cost more than the bytes saved.
// Over threads, each takes its contiguous rows (static_block, the split of first touch). A
// thread's rows write only its own rows and ring, except that its last W - 1 rows add into the
// next thread's first W - 1 rows: those sums stay in the ring, and after a barrier each thread
// adds its ring into those rows ("the spill": (threads - 1)(W - 1) synchronised updates a
// product, none of them atomic). W is at most the smallest thread's row count, so a spill stays
// inside the next thread's rows. The result depends on the thread count only through the spill's
// summation order.
#include <omp.h>

#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

#include "harness/kernel/blocks.hpp"
#include "kernels/fem/csr.hpp"

namespace suite::fem {

// The window the kernels ask for: 4096 rows, a ring of 32 KiB a thread (L1 or L2).
constexpr std::int64_t default_window = 4096;

// How the entries of a full pattern split, for a team of `threads`: counted before allocating.
struct SymmetricCounts {
    std::int64_t n = 0;
    int threads = 1;
    std::int64_t window = 1;     // W: the largest power of two <= the wanted one and every thread's rows
    int slots = 0;               // K: near upper entries a row holds, padding included
    std::uint64_t nnz = 0;       // of the full pattern
    std::uint64_t near_nnz = 0;  // the diagonal and the near upper entries (padding not counted)
    std::uint64_t far_nnz = 0;   // every other entry, counted in both rows
    std::int64_t far_rows = 0;   // rows with a far entry
    // Bytes of the structure a product reads, by the STREAM convention: the near values (K + 1 a
    // row) and columns (K a row), the far values and columns, the far rows' numbers and pointers.
    double matrix_bytes() const;
    // Entries of the full pattern the product applies: near_nnz counted twice off the diagonal.
    std::uint64_t applied() const { return 2 * near_nnz - static_cast<std::uint64_t>(n) + far_nnz; }
};

// slots_wanted negative: K is the smallest count of near upper entries that 95 % of the rows do not exceed.
SymmetricCounts count_symmetric(const Pattern& full, int threads, std::int64_t window_wanted, int slots_wanted = -1);

// The structure, on arrays the caller allocates from the counts.
struct SymmetricPattern {
    SymmetricCounts counts;
    std::uint32_t* col = nullptr;         // n * K: row i's near columns at K i (padding: i itself)
    std::uint32_t* far_row = nullptr;     // far_rows, ascending
    std::uint32_t* far_ptr = nullptr;     // far_rows + 1
    std::uint32_t* far_col = nullptr;     // far_nnz
    double* ring = nullptr;               // threads * ring_stride, all zero between products
    std::int64_t ring_stride = 0;         // ring_stride_for(W)
    std::vector<std::int64_t> far_first;  // threads + 1: thread t's far rows [far_first[t], far_first[t + 1])
    double* ring_of(int t) const { return ring + t * ring_stride + ring_skew; }
    // A thread's ring starts half a page and a line past a page boundary: slot j and x[j], y[j]
    // (page-aligned arrays) would otherwise share their low 12 address bits, and every load of
    // x[j] after a store to slot j would wait on it (4K aliasing).
    static constexpr std::int64_t ring_skew = 264;
};
inline std::int64_t ring_stride_for(std::int64_t window) { return (window + 7) / 8 * 8 + SymmetricPattern::ring_skew; }

struct SymmetricValues {
    const double* near = nullptr;  // n * (K + 1): row i's diagonal, then its K near values (padding: 0)
    const double* far = nullptr;
};

// Fills the structure from the full pattern (arrays written by the current team's row blocks, the
// split of first touch; the ring zeroed by its thread).
void fill_symmetric(const Pattern& full, SymmetricPattern& s);

// The values of one matrix in the structure. Returns "" or, when the matrix is not symmetric to
// within 1e-14 of the larger of a_ij and a_ji, what is wrong (the symmetric product would use
// a_ij for a_ji): the first such pair. Serial.
std::string fill_symmetric_values(const Pattern& full, const double* values, const SymmetricPattern& s, double* near,
                                  double* far);

// Rows [lo, hi) of thread t, whose far rows start at far row f: y_i, and on_row(i, y_i). Slots
// is K, a constant where the caller knows it (the loop unrolled whole), else 0 and K read.
template <int Slots, class OnRow>
inline std::int64_t symmetric_row_range(const SymmetricPattern& s, SymmetricValues v, const double* __restrict x,
                                        double* __restrict y, int t, std::int64_t lo, std::int64_t hi, std::int64_t f,
                                        OnRow&& on_row) {
    const std::uint32_t* __restrict col = s.col;
    const double* __restrict a = v.near;
    const std::int64_t slots = Slots > 0 ? Slots : s.counts.slots;
    double* __restrict ring = s.ring_of(t);
    const std::uint64_t mask = static_cast<std::uint64_t>(s.counts.window - 1);
    const std::int64_t f_end = s.far_first[static_cast<std::size_t>(t) + 1];
    std::int64_t next_far = f < f_end ? s.far_row[f] : -1;
    for (std::int64_t i = lo; i < hi; ++i) {
        const double* __restrict ai = a + (slots + 1) * i;
        const std::uint32_t* __restrict ci = col + slots * i;
        const double xi = x[i];
        double sum = ai[0] * xi;  // the diagonal
        for (std::int64_t q = 0; q < slots; ++q) {
            const std::uint32_t j = ci[q];
            const double aij = ai[q + 1];
            sum += aij * x[j];
            ring[j & mask] += aij * xi;
        }
        if (i == next_far) {
            for (std::uint32_t q = s.far_ptr[f], q_end = s.far_ptr[f + 1]; q < q_end; ++q)
                sum += v.far[q] * x[s.far_col[q]];
            ++f;
            next_far = f < f_end ? s.far_row[f] : -1;
        }
        double& slot = ring[static_cast<std::uint64_t>(i) & mask];
        const double yi = sum + slot;
        slot = 0;
        y[i] = yi;
        on_row(i, yi);
    }
    return f;
}

// Thread t's rows [b.lo, b.hi): y_i for every row, on_row(i, y_i) for those already final (all but
// the first W - 1 of a thread after the first, which the previous thread's spill completes).
template <class OnRow>
inline void symmetric_rows(const SymmetricPattern& s, SymmetricValues v, const double* x, double* y, int t, Block b,
                           OnRow&& on_row) {
    const std::int64_t deferred_end = t > 0 ? std::min(b.lo + s.counts.window - 1, b.hi) : b.lo;
    std::int64_t f = s.far_first[static_cast<std::size_t>(t)];
    auto both = [&]<int Slots>() {
        f = symmetric_row_range<Slots>(s, v, x, y, t, b.lo, deferred_end, f, [](std::int64_t, double) {});
        symmetric_row_range<Slots>(s, v, x, y, t, deferred_end, b.hi, f, on_row);
    };
    // The K of curve-ordered P1 meshes (3 or 4), unrolled; any other through the general loop.
    switch (s.counts.slots) {
        case 3:
            both.template operator()<3>();
            break;
        case 4:
            both.template operator()<4>();
            break;
        default:
            both.template operator()<0>();
            break;
    }
}

// Thread t's spill into the next thread's first W - 1 rows, after every thread's symmetric_rows.
template <class OnRow>
inline void symmetric_spill(const SymmetricPattern& s, double* y, int t, Block b, OnRow&& on_row) {
    if (t + 1 >= s.counts.threads) return;
    double* ring = s.ring_of(t);
    const std::uint64_t mask = static_cast<std::uint64_t>(s.counts.window - 1);
    const std::int64_t end = std::min(b.hi + s.counts.window - 1, s.counts.n);
    for (std::int64_t j = b.hi; j < end; ++j) {
        double& slot = ring[static_cast<std::uint64_t>(j) & mask];
        const double yj = y[j] + slot;
        slot = 0;
        y[j] = yj;
        on_row(j, yj);
    }
}

// y = A x by the whole team (of counts.threads threads); x must be whole (a barrier before). Ends
// with a barrier when the team has more than one thread: y is whole after it.
template <class OnRow>
inline void symmetric_product_team(const SymmetricPattern& s, SymmetricValues v, const double* x, double* y,
                                   OnRow&& on_row) {
    const int t = omp_get_thread_num();
    const Block b = static_block(s.counts.n, t, s.counts.threads);
    symmetric_rows(s, v, x, y, t, b, on_row);
    if (s.counts.threads > 1) {
#pragma omp barrier
        symmetric_spill(s, y, t, b, on_row);
#pragma omp barrier
    }
}

// The same product on one thread, thread by thread in the team's order: every y_i the team
// computes, to the last bit (the reference that catches a race).
void symmetric_product_replay(const SymmetricPattern& s, SymmetricValues v, const double* x, double* y);

// Owns its arrays: for tests and tools (the kernels allocate from their arena).
struct SymmetricMatrix {
    SymmetricPattern pattern;
    std::vector<std::uint32_t> col, far_row, far_ptr, far_col;
    std::vector<double> ring, near, far;
    SymmetricValues values() const { return {near.data(), far.data()}; }
};
// Builds the structure and one matrix's values; throws std::invalid_argument with
// fill_symmetric_values's reason when the matrix is not symmetric.
SymmetricMatrix make_symmetric(const Pattern& full, const double* values, int threads, std::int64_t window_wanted,
                               int slots_wanted = -1);

}  // namespace suite::fem
