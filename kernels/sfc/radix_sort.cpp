#include "kernels/sfc/radix_sort.hpp"

#include <omp.h>

#include <algorithm>
#include <cstring>
#include <vector>

#include "harness/kernel/blocks.hpp"

namespace suite::sfc {

namespace {

// Top-digit width: buckets of about 16 Ki pairs (192 KiB, inside an L2 cache), at most 2^12
// buckets so that the scatter of the first pass writes to few enough places at once.
int top_bits(std::size_t n, int key_bits) {
    int b = 1;
    while (b < 12 && (n >> (b + 14)) > 0) ++b;
    return std::min(b, key_bits);
}

// Finishes one bucket [lo, hi) of (keys_a, index_a): sorted by the low `bits` bits, result back
// in keys_a and perm.
void finish_bucket(std::size_t lo, std::size_t hi, int bits, std::uint32_t* perm, const SortBuffers& b) {
    const std::size_t n = hi - lo;
    std::uint64_t* ka = b.keys_a + lo;
    std::uint32_t* ia = b.index_a + lo;
    if (n < 48) {
        // Insertion sort on the key alone: stable, and the indices arrive ascending.
        for (std::size_t i = 1; i < n; ++i) {
            const std::uint64_t k = ka[i];
            const std::uint32_t x = ia[i];
            std::size_t j = i;
            for (; j > 0 && ka[j - 1] > k; --j) {
                ka[j] = ka[j - 1];
                ia[j] = ia[j - 1];
            }
            ka[j] = k;
            ia[j] = x;
        }
        std::memcpy(perm + lo, ia, n * sizeof *ia);
        return;
    }
    const int passes = (bits + 7) / 8;
    std::uint32_t count[8][256] = {};
    for (std::size_t i = 0; i < n; ++i)
        for (int p = 0; p < passes; ++p) ++count[p][(ka[i] >> (8 * p)) & 0xff];
    std::uint64_t *ks = ka, *kd = b.keys_b + lo;
    std::uint32_t *is = ia, *id = b.index_b + lo;
    for (int p = 0; p < passes; ++p) {
        std::uint32_t* c = count[p];
        if (*std::max_element(c, c + 256) == n) continue;  // one digit value for all: nothing moves
        std::uint32_t sum = 0;
        for (int d = 0; d < 256; ++d) {
            const std::uint32_t k = c[d];
            c[d] = sum;
            sum += k;
        }
        const int shift = 8 * p;
        for (std::size_t i = 0; i < n; ++i) {
            const std::uint32_t at = c[(ks[i] >> shift) & 0xff]++;
            kd[at] = ks[i];
            id[at] = is[i];
        }
        std::swap(ks, kd);
        std::swap(is, id);
    }
    std::memcpy(perm + lo, is, n * sizeof *is);
    if (ks != ka) std::memcpy(ka, ks, n * sizeof *ks);
}

}  // namespace

void sort_by_key(const std::uint64_t* keys, std::size_t n, int key_bits, std::uint32_t* perm, const SortBuffers& b) {
    if (n == 0) return;
    const int tb = top_bits(n, key_bits);
    const int shift = key_bits - tb;
    const std::size_t buckets = std::size_t{1} << tb;
    const int threads = omp_get_max_threads();
    // offset[t][d]: where thread t writes its first pair of digit d; starts as its count.
    std::vector<std::uint64_t> offset(static_cast<std::size_t>(threads) * buckets, 0);
    std::vector<std::uint64_t> bucket_start(buckets + 1, 0);
    const std::int64_t ni = static_cast<std::int64_t>(n);
#pragma omp parallel num_threads(threads)
    {
        const int t = omp_get_thread_num(), nt = omp_get_num_threads();
        const Block blk = static_block(ni, t, nt);
        std::uint64_t* mine = offset.data() + static_cast<std::size_t>(t) * buckets;
        for (std::int64_t i = blk.lo; i < blk.hi; ++i) ++mine[keys[i] >> shift];
#pragma omp barrier
#pragma omp single
        {
            // Bucket by bucket, thread by thread: the threads' blocks are in index order, so
            // pairs of one digit keep their index order (stability).
            std::uint64_t sum = 0;
            for (std::size_t d = 0; d < buckets; ++d) {
                bucket_start[d] = sum;
                for (int u = 0; u < nt; ++u) {
                    const std::uint64_t c = offset[static_cast<std::size_t>(u) * buckets + d];
                    offset[static_cast<std::size_t>(u) * buckets + d] = sum;
                    sum += c;
                }
            }
            bucket_start[buckets] = sum;
        }
        for (std::int64_t i = blk.lo; i < blk.hi; ++i) {
            const std::uint64_t at = mine[keys[i] >> shift]++;
            b.keys_a[at] = keys[i];
            b.index_a[at] = static_cast<std::uint32_t>(i);
        }
#pragma omp barrier
        const std::int64_t nb = static_cast<std::int64_t>(buckets);
#pragma omp for schedule(dynamic, 1)
        for (std::int64_t d = 0; d < nb; ++d) finish_bucket(bucket_start[d], bucket_start[d + 1], shift, perm, b);
    }
}

}  // namespace suite::sfc
