// The window scheme's structure (symmetric.hpp): counting, filling, the values, the serial replay.
#include "kernels/fem/symmetric.hpp"

#include <omp.h>

#include <cmath>
#include <stdexcept>

#include "harness/common/units.hpp"

namespace suite::fem {

namespace {

// Which entries of the full pattern are near (in row i's K slots) and which far, for a window W.
class Split {
public:
    Split(const Pattern& full, std::int64_t w, int k)
        : p_(full), w_(w), k_(k), upper_(static_cast<std::size_t>(full.n)) {
        for (std::int64_t i = 0; i < full.n; ++i) {
            std::uint32_t q = full.row_ptr[i];
            while (q < full.row_ptr[i + 1] && full.col[q] < i) ++q;
            if (q == full.row_ptr[i + 1] || full.col[q] != i)
                throw std::invalid_argument("row " + std::to_string(i) +
                                            " has no diagonal entry; --strategy=symmetric needs one in every row");
            upper_[static_cast<std::size_t>(i)] = q + 1;
        }
    }
    // Entry q of row i, column j > i: near when within the window and among the row's first K.
    bool near_upper(std::int64_t i, std::uint32_t q) const {
        return p_.col[q] - i < w_ && q - upper_[static_cast<std::size_t>(i)] < static_cast<std::uint32_t>(k_);
    }
    bool far(std::int64_t i, std::uint32_t q) const {
        const std::int64_t j = p_.col[q];
        if (j == i) return false;
        if (j > i) return !near_upper(i, q);
        const std::int64_t t = find_entry(p_, static_cast<std::uint32_t>(j), static_cast<std::uint32_t>(i));
        return t < 0 || !near_upper(j, static_cast<std::uint32_t>(t));
    }
    std::uint32_t upper(std::int64_t i) const { return upper_[static_cast<std::size_t>(i)]; }

private:
    const Pattern& p_;
    std::int64_t w_;
    int k_;
    std::vector<std::uint32_t> upper_;  // a row's first entry right of the diagonal
};

}  // namespace

double SymmetricCounts::matrix_bytes() const {
    const double nd = static_cast<double>(n), k = slots;
    return 8.0 * (k + 1) * nd + 4.0 * k * nd + 12.0 * static_cast<double>(far_nnz) +
           8.0 * static_cast<double>(far_rows) + 4.0;
}

SymmetricCounts count_symmetric(const Pattern& full, int threads, std::int64_t window_wanted, int slots_wanted) {
    SymmetricCounts c;
    c.n = full.n;
    c.threads = threads;
    c.nnz = full.nnz();
    std::int64_t smallest = full.n;
    for (int t = 0; t < threads; ++t) {
        const Block b = static_block(full.n, t, threads);
        smallest = std::min(smallest, b.hi - b.lo);
    }
    const std::int64_t limit = std::max<std::int64_t>(1, std::min(window_wanted, smallest));
    while (c.window * 2 <= limit) c.window *= 2;
    c.slots = slots_wanted;
    if (slots_wanted < 0) {
        // The smallest K that 95 % of the rows do not exceed.
        std::vector<std::int64_t> rows_with(64, 0);
        for (std::int64_t i = 0; i < full.n; ++i) {
            std::int64_t u = 0;
            for (std::uint32_t q = full.row_ptr[i]; q < full.row_ptr[i + 1]; ++q)
                u += full.col[q] > i && full.col[q] - i < c.window;
            ++rows_with[static_cast<std::size_t>(std::min<std::int64_t>(u, 63))];
        }
        std::int64_t covered = 0;
        c.slots = 0;
        while (c.slots < 63 && static_cast<double>(covered += rows_with[static_cast<std::size_t>(c.slots)]) <
                                   0.95 * static_cast<double>(full.n))
            ++c.slots;
    }
    const Split split(full, c.window, c.slots);
    for (std::int64_t i = 0; i < full.n; ++i) {
        bool far = false;
        for (std::uint32_t q = full.row_ptr[i]; q < full.row_ptr[i + 1]; ++q) {
            if (full.col[q] == i || (full.col[q] > i && split.near_upper(i, q))) ++c.near_nnz;
            if (split.far(i, q)) ++c.far_nnz, far = true;
        }
        c.far_rows += far;
    }
    return c;
}

void fill_symmetric(const Pattern& full, SymmetricPattern& s) {
    const SymmetricCounts& c = s.counts;
    const Split split(full, c.window, c.slots);
    const std::int64_t k = c.slots;
    // Offsets of the far rows first (serially: setup), then each thread copies its rows, touching
    // them first.
    std::int64_t fr = 0;
    std::uint64_t far = 0;
    s.far_first.assign(static_cast<std::size_t>(c.threads) + 1, 0);
    std::vector<std::int64_t> far_slot(static_cast<std::size_t>(c.n), -1);
    std::vector<std::uint32_t> far_start(static_cast<std::size_t>(c.far_rows) + 1);
    int owner = 0;
    for (std::int64_t i = 0; i < c.n; ++i) {
        while (i >= static_block(c.n, owner, c.threads).hi) s.far_first[static_cast<std::size_t>(++owner)] = fr;
        std::uint64_t row_far = 0;
        for (std::uint32_t q = full.row_ptr[i]; q < full.row_ptr[i + 1]; ++q) row_far += split.far(i, q);
        if (row_far) {
            far_slot[static_cast<std::size_t>(i)] = fr;
            far_start[static_cast<std::size_t>(fr++)] = static_cast<std::uint32_t>(far);
            far += row_far;
        }
    }
    while (owner < c.threads) s.far_first[static_cast<std::size_t>(++owner)] = fr;
    far_start[static_cast<std::size_t>(fr)] = static_cast<std::uint32_t>(far);
    if (far != c.far_nnz || fr != c.far_rows)
        throw std::logic_error("fill_symmetric: the counts are not this pattern's");
    const SymmetricPattern& o = s;
    // One iteration a thread's rows: each team member fills (and first touches) its own.
#pragma omp parallel for num_threads(c.threads) schedule(static, 1)
    for (int t = 0; t < c.threads; ++t) {
        const Block b = static_block(c.n, t, c.threads);
        for (std::int64_t i = b.lo; i < b.hi; ++i) {
            std::uint32_t* ci = o.col + k * i;
            std::int64_t used = 0;
            const std::int64_t slot = far_slot[static_cast<std::size_t>(i)];
            std::uint32_t kf = slot >= 0 ? far_start[static_cast<std::size_t>(slot)] : 0;
            if (slot >= 0) o.far_row[slot] = static_cast<std::uint32_t>(i), o.far_ptr[slot] = kf;
            for (std::uint32_t q = full.row_ptr[i]; q < full.row_ptr[i + 1]; ++q) {
                const std::uint32_t j = full.col[q];
                if (j > i && split.near_upper(i, q)) ci[used++] = j;
                if (split.far(i, q)) o.far_col[kf++] = j;
            }
            for (; used < k; ++used)
                ci[used] = static_cast<std::uint32_t>(i);  // padding: a zero value at the row's own column
        }
        std::fill(o.ring + t * o.ring_stride, o.ring + (t + 1) * o.ring_stride, 0.0);
    }
    s.far_ptr[fr] = static_cast<std::uint32_t>(far);
}

std::string fill_symmetric_values(const Pattern& full, const double* values, const SymmetricPattern& s, double* near,
                                  double* far) {
    const Split split(full, s.counts.window, s.counts.slots);
    const std::int64_t k = s.counts.slots;
    std::uint64_t kf = 0;
    for (std::int64_t i = 0; i < full.n; ++i) {
        double* ai = near + (k + 1) * i;
        std::int64_t used = 0;
        for (std::uint32_t q = full.row_ptr[i]; q < full.row_ptr[i + 1]; ++q) {
            const std::int64_t j = full.col[q];
            if (split.far(i, q)) far[kf++] = values[q];
            if (j == i) ai[0] = values[q];
            if (!(j > i && split.near_upper(i, q))) continue;
            ai[1 + used++] = values[q];
            const std::int64_t kt = find_entry(full, static_cast<std::uint32_t>(j), static_cast<std::uint32_t>(i));
            const double aij = values[q], aji = kt < 0 ? 0.0 : values[kt];
            if (!(std::fabs(aij - aji) <= 1e-14 * std::max(std::fabs(aij), std::fabs(aji))))
                return "the matrix is not symmetric: A[" + std::to_string(i) + "][" + std::to_string(j) +
                       "] = " + format_number(aij) + " but A[" + std::to_string(j) + "][" + std::to_string(i) +
                       "] = " + (kt < 0 ? std::string("not stored") : format_number(aji)) +
                       "; --strategy=symmetric stores one triangle and needs a_ij = a_ji (use --strategy=csr)";
        }
        for (; used < k; ++used) ai[1 + used] = 0.0;
    }
    return "";
}

void symmetric_product_replay(const SymmetricPattern& s, SymmetricValues v, const double* x, double* y) {
    const int nt = s.counts.threads;
    auto none = [](std::int64_t, double) {};
    for (int t = 0; t < nt; ++t) symmetric_rows(s, v, x, y, t, static_block(s.counts.n, t, nt), none);
    for (int t = 0; t < nt; ++t) symmetric_spill(s, y, t, static_block(s.counts.n, t, nt), none);
}

SymmetricMatrix make_symmetric(const Pattern& full, const double* values, int threads, std::int64_t window_wanted,
                               int slots_wanted) {
    SymmetricMatrix m;
    SymmetricPattern& s = m.pattern;
    s.counts = count_symmetric(full, threads, window_wanted, slots_wanted);
    const SymmetricCounts& c = s.counts;
    const std::size_t n = static_cast<std::size_t>(c.n), k = static_cast<std::size_t>(c.slots);
    m.col.resize(n * k + 1);
    m.far_row.resize(static_cast<std::size_t>(c.far_rows) + 1);
    m.far_ptr.resize(static_cast<std::size_t>(c.far_rows) + 1);
    m.far_col.resize(c.far_nnz + 1);
    s.ring_stride = ring_stride_for(c.window);
    m.ring.resize(static_cast<std::size_t>(s.ring_stride * c.threads));
    m.near.resize(n * (k + 1));
    m.far.resize(c.far_nnz + 1);
    s.col = m.col.data();
    s.far_row = m.far_row.data();
    s.far_ptr = m.far_ptr.data();
    s.far_col = m.far_col.data();
    s.ring = m.ring.data();
    fill_symmetric(full, s);
    const std::string wrong = fill_symmetric_values(full, values, s, m.near.data(), m.far.data());
    if (!wrong.empty()) throw std::invalid_argument(wrong);
    return m;
}

}  // namespace suite::fem
