// Reordering: the stable parallel sort against std::stable_sort, first-touch renumbering
// against a serial loop, whole-mesh reorderings keeping every element's geometry, RCM against
// random, the quality numbers on hand-made meshes, and sfc-build's checks catching wrong answers.
#include <gtest/gtest.h>

#include <omp.h>

#include <algorithm>
#include <numeric>
#include <random>

#include "kernels/mesh/generate.hpp"
#include "kernels/sfc/pipeline.hpp"
#include "kernels/sfc/quality.hpp"
#include "kernels/sfc/sfc_checks.hpp"

using namespace suite::sfc;
using suite::mesh::Mesh;

namespace {

// Runs `f` with 1 and then 2 OpenMP threads.
template <class F>
void with_threads(F f) {
    const int saved = omp_get_max_threads();
    for (int t : {1, 2}) {
        omp_set_num_threads(t);
        SCOPED_TRACE(std::to_string(t) + " thread(s)");
        f();
    }
    omp_set_num_threads(saved);
}

std::vector<std::uint32_t> sorted_by_key(const std::vector<std::uint64_t>& keys, int bits) {
    const std::size_t n = keys.size();
    std::vector<std::uint64_t> ka(n), kb(n);
    std::vector<std::uint32_t> ia(n), ib(n), perm(n);
    sort_by_key(keys.data(), n, bits, perm.data(), {ka.data(), kb.data(), ia.data(), ib.data()});
    std::vector<std::uint64_t> expect_sorted = keys;
    std::sort(expect_sorted.begin(), expect_sorted.end());
    EXPECT_EQ(ka, expect_sorted) << "buffers.keys_a holds the sorted keys";
    return perm;
}

// The serial definition of first-touch numbering.
std::vector<std::uint32_t> first_touch_serial(const Mesh& m, const std::vector<std::uint32_t>& perm) {
    std::vector<std::uint32_t> id(m.vertices(), UINT32_MAX);
    std::uint32_t next = 0;
    const int k = m.corners();
    for (auto e : perm)
        for (int j = 0; j < k; ++j)
            if (id[m.conn[e * k + j]] == UINT32_MAX) id[m.conn[e * k + j]] = next++;
    for (auto& v : id)
        if (v == UINT32_MAX) v = next++;
    return id;
}

// Element i of `r` is element perm[i] of `m`, corner for corner, at the same coordinates.
void expect_same_elements(const Mesh& m, const Reordered& r) {
    const int k = m.corners();
    ASSERT_EQ(r.mesh.conn.size(), m.conn.size());
    for (std::size_t i = 0; i < m.elements(); ++i)
        for (int j = 0; j < k; ++j) {
            const auto a = m.conn[r.perm[i] * k + j], b = r.mesh.conn[i * k + j];
            ASSERT_EQ(r.mesh.x[b], m.x[a]);
            ASSERT_EQ(r.mesh.y[b], m.y[a]);
            if (m.dim == 3) {
                ASSERT_EQ(r.mesh.z[b], m.z[a]);
            }
        }
}

}  // namespace

TEST(SfcSort, StableAndSortedLikeStdStableSort) {
    std::mt19937_64 rng(11);
    with_threads([&] {
        for (std::size_t n : {0u, 1u, 5u, 47u, 48u, 49u, 1000u, 70000u, 140000u})
            for (int bits : {1, 3, 12, 20, 64}) {
                std::vector<std::uint64_t> keys(n);
                for (auto& k : keys) k = bits == 64 ? rng() : rng() & ((1ULL << bits) - 1);
                std::vector<std::uint32_t> expect(n);
                std::iota(expect.begin(), expect.end(), 0u);
                std::stable_sort(expect.begin(), expect.end(), [&](auto a, auto b) { return keys[a] < keys[b]; });
                ASSERT_EQ(sorted_by_key(keys, bits), expect) << "n " << n << " bits " << bits;
            }
    });
}

TEST(SfcRenumber, FirstTouchMatchesTheSerialLoop) {
    Mesh m = suite::mesh::disk_mesh(4);
    // One vertex no element touches: numbered after all the others.
    m.x.push_back(5);
    m.y.push_back(5);
    std::vector<std::uint32_t> perm(m.elements());
    std::iota(perm.begin(), perm.end(), 0u);
    std::shuffle(perm.begin(), perm.end(), std::mt19937_64(12));
    const auto expect = first_touch_serial(m, perm);
    EXPECT_EQ(expect.back(), m.vertices() - 1);
    with_threads([&] {
        std::vector<std::uint32_t> id(m.vertices()), first(m.vertices()), conn(m.conn.size()),
            rank(rank_words(m.elements(), 3));
        std::vector<std::uint64_t> bits(rank.size());
        std::vector<double> x(m.vertices()), y(m.vertices());
        renumber_first_touch(m.view(), perm.data(), id.data(), {first.data(), bits.data(), rank.data()},
                             {conn.data(), x.data(), y.data(), nullptr});
        EXPECT_EQ(id, expect);
        for (std::size_t v = 0; v < m.vertices(); ++v) ASSERT_EQ(x[id[v]], m.x[v]);
        for (std::size_t p = 0; p < conn.size(); ++p) ASSERT_EQ(conn[p], id[m.conn[perm[p / 3] * 3 + p % 3]]);
    });
}

TEST(SfcReorder, EveryMethodKeepsEveryElementAndSortsItsKeys) {
    for (const Mesh& m : {suite::mesh::disk_mesh(4), suite::mesh::box_mesh(4, 3, 5)}) {
        for (Method method : {Method::morton, Method::hilbert, Method::morton_recursive, Method::rcm}) {
            SCOPED_TRACE("dim " + std::to_string(m.dim) + " method " + std::to_string(static_cast<int>(method)));
            const Reordered r = reorder(m, method, max_depth(m.dim));
            expect_same_elements(m, r);
            if (method == Method::rcm) continue;
            const Curve c = method == Method::hilbert ? Curve::hilbert : Curve::morton;
            std::vector<std::uint64_t> keys(m.elements());
            compute_keys(r.mesh.view(), key_frame(r.mesh.view(), max_depth(m.dim)), c, keys.data());
            EXPECT_TRUE(std::is_sorted(keys.begin(), keys.end()));
        }
        const Reordered a = reorder(m, Method::morton, max_depth(m.dim));
        const Reordered b = reorder(m, Method::morton_recursive, max_depth(m.dim));
        EXPECT_EQ(a.mesh.conn, b.mesh.conn);  // the same keys give the same mesh
        expect_same_elements(m, shuffled(m, 3));
    }
}

TEST(SfcQuality, RcmBandwidthFarBelowRandom) {
    for (const Mesh& m : {suite::mesh::disk_mesh(5), suite::mesh::box_mesh(6, 6, 6)}) {
        const OrderingQuality random = ordering_quality(shuffled(m, 1).mesh);
        const OrderingQuality rcm = ordering_quality(reorder(m, Method::rcm, 1).mesh);
        const OrderingQuality morton = ordering_quality(reorder(m, Method::morton, max_depth(m.dim)).mesh);
        // 343 vertices of a small cube leave less room than the disk's 3169: a factor 3 for all.
        EXPECT_LT(rcm.bandwidth * 5, random.bandwidth) << "dim " << m.dim;
        EXPECT_LT(rcm.profile * 3, random.profile) << "dim " << m.dim;
        EXPECT_LT(morton.spread_mean * 3, random.spread_mean) << "dim " << m.dim;
    }
}

TEST(SfcQuality, NumbersOfHandMadeMeshes) {
    // Two triangles of a square: edges 01 12 20 23 30.
    Mesh sq;
    sq.x = {0, 1, 1, 0};
    sq.y = {0, 0, 1, 1};
    sq.conn = {0, 1, 2, 0, 2, 3};
    const OrderingQuality q = ordering_quality(sq);
    EXPECT_EQ(q.bandwidth, 3u);
    EXPECT_EQ(q.profile, 1u + 2u + 3u);  // rows 1, 2, 3 each reach back to column 0
    EXPECT_DOUBLE_EQ(q.spread_mean, 2.5);
    EXPECT_EQ(q.spread_p95, 3u);
    // A strip of 4 triangles split in 2 blocks: vertices 2 and 3 are in both halves.
    Mesh strip;
    strip.x = {0, 0, 1, 1, 2, 2};
    strip.y = {0, 1, 0, 1, 0, 1};
    strip.conn = {0, 2, 1, 1, 2, 3, 2, 4, 3, 3, 4, 5};
    const ThreadSharing s2 = thread_sharing(strip.view(), 2);
    EXPECT_EQ(s2.vertices, 2u);
    EXPECT_EQ(s2.elements, 4u);
    EXPECT_EQ(thread_sharing(strip.view(), 1).elements, 0u);
    EXPECT_EQ(thread_block(10, 0, 3),
              (std::pair<std::uint64_t, std::uint64_t>{0, 4}));  // the first n % threads blocks are longer
    EXPECT_EQ(thread_block(10, 2, 3), (std::pair<std::uint64_t, std::uint64_t>{7, 10}));
}

TEST(SfcChecks, CatchWrongAnswersNotJustMissingOnes) {
    const Mesh m = suite::mesh::disk_mesh(3);
    const std::size_t ne = m.elements(), nv = m.vertices();
    std::vector<std::uint64_t> keys(ne), ka(ne), kb(ne);
    std::vector<std::uint32_t> perm(ne), ia(ne), ib(ne), id(nv), first(nv), conn(m.conn.size()),
        rank(rank_words(ne, 3));
    std::vector<std::uint64_t> bits(rank.size());
    std::vector<double> x(nv), y(nv);
    const PipelineArrays a{keys.data(),
                           perm.data(),
                           {ka.data(), kb.data(), ia.data(), ib.data()},
                           id.data(),
                           {first.data(), bits.data(), rank.data()},
                           {conn.data(), x.data(), y.data(), nullptr}};
    Pipeline p(m.view(), Method::hilbert, 32, Encoder::best, a);
    p.keys();
    p.sort();
    p.renumber();
    const Checks checks(m.view(), Method::hilbert, 32, a, p.frame());
    EXPECT_TRUE(checks.keys().passed);
    EXPECT_TRUE(checks.sort().passed);
    EXPECT_TRUE(checks.renumber().passed) << checks.renumber().failure;
    keys[5] ^= 1;  // the lowest bit: a neighbouring cell
    EXPECT_FALSE(checks.keys().passed);
    keys[5] ^= 1;
    std::swap(perm[10], perm[20]);
    EXPECT_FALSE(checks.sort().passed);
    std::swap(perm[10], perm[20]);
    x[7] += 1e-12;
    EXPECT_FALSE(checks.renumber().passed);
    x[7] -= 1e-12;
    // Vertices 0 and 1 trade numbers everywhere: a consistent mesh, but not in first-touch order.
    for (auto& c : conn) c = c == 0 ? 1 : c == 1 ? 0 : c;
    for (auto& v : id) v = v == 0 ? 1 : v == 1 ? 0 : v;
    std::swap(x[0], x[1]);
    std::swap(y[0], y[1]);
    const auto r = checks.renumber();
    EXPECT_FALSE(r.passed);
    EXPECT_NE(r.failure.find("before its first touch"), std::string::npos) << r.failure;
}
