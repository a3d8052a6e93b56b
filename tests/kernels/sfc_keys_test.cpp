// Space-filling-curve keys: known values, BMI2 pdep against the portable interleave, the
// thesis's recursive halving against quantize-and-interleave, Hilbert against the classic
// rotate-and-reflect algorithm and its defining property (consecutive cells are neighbours),
// decoders as inverses, keys at depth d as prefixes of deeper keys, and whole meshes.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <set>

#include "kernels/mesh/generate.hpp"
#include "kernels/sfc/keys.hpp"
#include "kernels/sfc/quality.hpp"

using namespace suite::sfc;
using suite::mesh::Mesh;

namespace {

// The 2D Hilbert index by the textbook rotate-and-reflect loop, written independently of
// Skilling's transform, walking from the top bit down.
std::uint64_t hilbert_classic(std::uint32_t x, std::uint32_t y, int depth) {
    std::uint64_t d = 0;
    for (std::uint64_t s = 1ULL << (depth - 1); s > 0; s >>= 1) {
        const std::uint64_t rx = (x & s) ? 1 : 0, ry = (y & s) ? 1 : 0;
        d += s * s * ((3 * rx) ^ ry);
        if (ry == 0) {
            if (rx == 1) {
                x = static_cast<std::uint32_t>(s - 1 - (x & (s - 1))) | (x & ~static_cast<std::uint32_t>(s - 1));
                y = static_cast<std::uint32_t>(s - 1 - (y & (s - 1))) | (y & ~static_cast<std::uint32_t>(s - 1));
            }
            std::swap(x, y);
        }
    }
    return d;
}

template <int Dim>
std::uint64_t hilbert(std::uint32_t const* q, int depth) {
    return hilbert_key<Dim, false>(q, depth);
}

std::vector<std::array<std::uint32_t, 3>> random_cells(int dim, int depth, std::size_t n, std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    const std::uint64_t mask = depth == 32 ? 0xffffffffULL : (1ULL << depth) - 1;
    std::vector<std::array<std::uint32_t, 3>> out(n);
    for (auto& q : out)
        for (int a = 0; a < dim; ++a) q[a] = static_cast<std::uint32_t>(rng() & mask);
    out.push_back({static_cast<std::uint32_t>(mask), static_cast<std::uint32_t>(mask),
                   dim == 3 ? static_cast<std::uint32_t>(mask) : 0});
    out.push_back({0, 0, 0});
    return out;
}

}  // namespace

TEST(SfcKeys, MortonKnownValues) {
    const std::uint32_t a[3] = {3, 5, 0};  // x = 011, y = 101 -> y2 x2 y1 x1 y0 x0 = 10 01 11
    EXPECT_EQ(morton_portable<2>(a), 0b100111u);
    const std::uint32_t b[3] = {1, 2, 4};  // x0, y1, z2 -> bits 0, 4, 8
    EXPECT_EQ(morton_portable<3>(b), 0x111u);
    const std::uint32_t c[3] = {0xffffffffu, 0, 0};
    EXPECT_EQ(morton_portable<2>(c), 0x5555555555555555ULL);
    const std::uint32_t d[3] = {0x1fffff, 0x1fffff, 0x1fffff};
    EXPECT_EQ(morton_portable<3>(d), 0x7fffffffffffffffULL);
    EXPECT_EQ(max_depth(2), 32);
    EXPECT_EQ(max_depth(3), 21);
}

TEST(SfcKeys, PdepAndPortableGiveIdenticalKeys) {
    if (!have_pdep)
        GTEST_SKIP() << "this build's -march has no BMI2, so the pdep path is not compiled (the portable one is used)";
    for (const auto& q : random_cells(2, 32, 200000, 1))
        ASSERT_EQ(morton_pdep<2>(q.data()), morton_portable<2>(q.data()));
    for (const auto& q : random_cells(3, 21, 200000, 2))
        ASSERT_EQ(morton_pdep<3>(q.data()), morton_portable<3>(q.data()));
    for (const auto& q : random_cells(2, 32, 20000, 3))
        ASSERT_EQ((hilbert_key<2, true>(q.data(), 32)), (hilbert_key<2, false>(q.data(), 32)));
    for (const auto& q : random_cells(3, 21, 20000, 4))
        ASSERT_EQ((hilbert_key<3, true>(q.data(), 21)), (hilbert_key<3, false>(q.data(), 21)));
}

TEST(SfcKeys, RecursiveHalvingEqualsQuantizeAndInterleave) {
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    std::vector<double> ts = {0.0, 0x1.fffffffffffffp-1, 0.5, std::nextafter(0.5, 0.0), 0.25, 0.75, 1.0 / 3};
    for (int d = 1; d <= 32; ++d) {  // cell boundaries, and the doubles just below them
        ts.push_back(std::ldexp(1.0, -d));
        ts.push_back(std::nextafter(std::ldexp(1.0, -d), 0.0));
        ts.push_back(1 - std::ldexp(1.0, -d));
    }
    for (int i = 0; i < 100000; ++i) ts.push_back(u(rng));
    for (int depth : {1, 5, 16, 21, 31, 32}) {
        for (std::size_t i = 0; i < ts.size(); ++i) {
            const double t2[3] = {ts[i], ts[(i * 7 + 3) % ts.size()], 0};
            const std::uint32_t q2[3] = {quantize(t2[0], depth), quantize(t2[1], depth), 0};
            ASSERT_EQ(morton_recursive<2>(t2, depth), morton_portable<2>(q2))
                << "depth " << depth << " t " << t2[0] << " " << t2[1];
            if (depth > 21) continue;
            const double t3[3] = {ts[i], ts[(i * 5 + 1) % ts.size()], ts[(i * 11 + 2) % ts.size()]};
            const std::uint32_t q3[3] = {quantize(t3[0], depth), quantize(t3[1], depth), quantize(t3[2], depth)};
            ASSERT_EQ(morton_recursive<3>(t3, depth), morton_portable<3>(q3)) << "depth " << depth;
        }
    }
}

TEST(SfcKeys, HilbertKnownValuesAndClassicAlgorithm) {
    const std::uint32_t cells[4][3] = {{0, 0, 0}, {0, 1, 0}, {1, 1, 0}, {1, 0, 0}};  // the order of the first level
    for (std::uint64_t i = 0; i < 4; ++i) EXPECT_EQ(hilbert<2>(cells[i], 1), i);
    for (int depth = 1; depth <= 6; ++depth)
        for (std::uint32_t x = 0; x < (1u << depth); ++x)
            for (std::uint32_t y = 0; y < (1u << depth); ++y) {
                const std::uint32_t q[3] = {x, y, 0};
                ASSERT_EQ(hilbert<2>(q, depth), hilbert_classic(x, y, depth))
                    << "depth " << depth << " (" << x << ", " << y << ")";
            }
    for (const auto& q : random_cells(2, 32, 10000, 6))
        ASSERT_EQ(hilbert<2>(q.data(), 32), hilbert_classic(q[0], q[1], 32));
}

TEST(SfcKeys, HilbertTablesGiveTheDefiningTransformsKeysAtEveryDepth) {
    // The fast key is a table walk built from the transform at compile time; here it is held
    // to the transform itself, at every depth (those that are not a multiple of the lookup's
    // levels take the padded path) and through both interleaves.
    EXPECT_EQ(HilbertTables<2>::states, 4);   // the square's curve has 4 orientations
    EXPECT_EQ(HilbertTables<3>::states, 24);  // the cube's: 24 (Skilling's curve, as the literature counts it)
    for (int d = 1; d <= 32; ++d)
        for (const auto& q : random_cells(2, d, 3000, 100 + d)) {
            ASSERT_EQ((hilbert_key<2, false>(q.data(), d)), hilbert_key_reference<2>(q.data(), d)) << "depth " << d;
            ASSERT_EQ((hilbert_key<2, have_pdep>(q.data(), d)), hilbert_key_reference<2>(q.data(), d)) << "depth " << d;
        }
    for (int d = 1; d <= 21; ++d)
        for (const auto& q : random_cells(3, d, 3000, 200 + d)) {
            ASSERT_EQ((hilbert_key<3, false>(q.data(), d)), hilbert_key_reference<3>(q.data(), d)) << "depth " << d;
            ASSERT_EQ((hilbert_key<3, have_pdep>(q.data(), d)), hilbert_key_reference<3>(q.data(), d)) << "depth " << d;
        }
}

TEST(SfcKeys, HilbertRunsOfKeysEqualKeysOneAtATime) {
    // The run converts four keys in lock step and the rest one by one: every remainder, and a
    // depth off the lookup's grid.
    for (int d : {32, 13}) {
        const auto cells = random_cells(2, d, 11, 300 + d);
        for (std::size_t n = 0; n <= cells.size(); ++n) {
            std::vector<std::uint64_t> run(n);
            for (std::size_t i = 0; i < n; ++i) run[i] = morton_portable<2>(cells[i].data());
            hilbert_from_morton_run<2>(run.data(), n, d);
            for (std::size_t i = 0; i < n; ++i)
                ASSERT_EQ(run[i], hilbert_key_reference<2>(cells[i].data(), d)) << "n " << n << " i " << i;
        }
    }
    const auto cells = random_cells(3, 20, 9, 400);
    std::vector<std::uint64_t> run;
    for (const auto& q : cells) run.push_back(morton_portable<3>(q.data()));
    hilbert_from_morton_run<3>(run.data(), run.size(), 20);
    for (std::size_t i = 0; i < cells.size(); ++i) ASSERT_EQ(run[i], hilbert_key_reference<3>(cells[i].data(), 20));
}

TEST(SfcKeys, HilbertVisitsNeighboursInTurnOnceEach) {
    for (int dim : {2, 3})
        for (int depth = 1; depth <= (dim == 2 ? 6 : 4); ++depth) {
            SCOPED_TRACE("dim " + std::to_string(dim) + " depth " + std::to_string(depth));
            const std::uint64_t n = 1ULL << (dim * depth);
            std::set<std::array<std::uint32_t, 3>> seen;
            std::array<std::uint32_t, 3> prev{};
            for (std::uint64_t key = 0; key < n; ++key) {
                std::array<std::uint32_t, 3> q{};
                dim == 2 ? hilbert_decode<2>(key, depth, q.data()) : hilbert_decode<3>(key, depth, q.data());
                ASSERT_EQ(dim == 2 ? hilbert<2>(q.data(), depth) : hilbert<3>(q.data(), depth), key);
                ASSERT_TRUE(seen.insert(q).second);
                if (key > 0) {
                    int steps = 0;
                    for (int a = 0; a < 3; ++a) steps += std::abs(static_cast<int>(q[a]) - static_cast<int>(prev[a]));
                    ASSERT_EQ(steps, 1) << "key " << key << " is not next to key " << key - 1;
                }
                prev = q;
            }
            EXPECT_EQ(seen.size(), n);
        }
}

TEST(SfcKeys, DecodersInvertEncodersAtFullDepth) {
    for (const auto& q : random_cells(2, 32, 50000, 7)) {
        std::uint32_t back[3] = {};
        morton_decode<2>(morton_portable<2>(q.data()), 32, back);
        ASSERT_TRUE(back[0] == q[0] && back[1] == q[1]);
        hilbert_decode<2>(hilbert<2>(q.data(), 32), 32, back);
        ASSERT_TRUE(back[0] == q[0] && back[1] == q[1]);
    }
    for (const auto& q : random_cells(3, 21, 50000, 8)) {
        std::uint32_t back[3] = {};
        morton_decode<3>(morton_portable<3>(q.data()), 21, back);
        ASSERT_TRUE(back[0] == q[0] && back[1] == q[1] && back[2] == q[2]);
        hilbert_decode<3>(hilbert<3>(q.data(), 21), 21, back);
        ASSERT_TRUE(back[0] == q[0] && back[1] == q[1] && back[2] == q[2]);
    }
}

TEST(SfcKeys, ShallowKeysArePrefixesOfDeepOnes) {
    // What lets one sorted key list answer "how many elements share a key" at every depth.
    for (const auto& q : random_cells(2, 32, 2000, 9))
        for (int d = 1; d < 32; ++d) {
            const std::uint32_t s[3] = {q[0] >> (32 - d), q[1] >> (32 - d), 0};
            ASSERT_EQ(hilbert<2>(q.data(), 32) >> (2 * (32 - d)), hilbert<2>(s, d));
            ASSERT_EQ(morton_portable<2>(q.data()) >> (2 * (32 - d)), morton_portable<2>(s));
        }
    for (const auto& q : random_cells(3, 21, 2000, 10))
        for (int d = 1; d < 21; ++d) {
            const std::uint32_t s[3] = {q[0] >> (21 - d), q[1] >> (21 - d), q[2] >> (21 - d)};
            ASSERT_EQ(hilbert<3>(q.data(), 21) >> (3 * (21 - d)), hilbert<3>(s, d));
        }
}

TEST(SfcKeys, MeshKeysAgreeAcrossEncodersAndTheRecursiveReference) {
    for (const Mesh& m : {suite::mesh::disk_mesh(5), suite::mesh::box_mesh(5, 4, 3)}) {
        const auto v = m.view();
        const KeyFrame f = key_frame(v, max_depth(m.dim));
        EXPECT_DOUBLE_EQ(f.lo[0], *std::min_element(m.x.begin(), m.x.end()));
        EXPECT_DOUBLE_EQ(1 / f.scale[1],
                         *std::max_element(m.y.begin(), m.y.end()) - *std::min_element(m.y.begin(), m.y.end()));
        std::vector<std::uint64_t> best(m.elements()), portable(m.elements()), recursive(m.elements()),
            hb(m.elements()), hp(m.elements());
        compute_keys(v, f, Curve::morton, best.data(), Encoder::best);
        compute_keys(v, f, Curve::morton, portable.data(), Encoder::portable);
        compute_keys(v, f, Curve::morton_recursive, recursive.data());
        compute_keys(v, f, Curve::hilbert, hb.data(), Encoder::best);
        compute_keys(v, f, Curve::hilbert, hp.data(), Encoder::portable);
        EXPECT_EQ(best, portable);
        EXPECT_EQ(best, recursive);
        EXPECT_EQ(hb, hp);
        EXPECT_NE(best, hb);
        EXPECT_GT(std::set<std::uint64_t>(best.begin(), best.end()).size(),
                  m.elements() * 99 / 100);  // deep keys tell elements apart
        for (std::size_t e = 0; e < m.elements(); e += 37)
            EXPECT_EQ(element_key(v, f, Curve::hilbert, e, Encoder::portable), hb[e]);
    }
}

TEST(SfcKeys, SharedKeyFractionFallsWithDepthTheSameForEveryCurve) {
    const Mesh m = suite::mesh::disk_mesh(4);
    const auto morton = shared_key_fraction(m.view(), Curve::morton);
    const auto hilbert_f = shared_key_fraction(m.view(), Curve::hilbert);
    ASSERT_EQ(morton.size(), 32u);
    EXPECT_EQ(morton, hilbert_f);
    EXPECT_EQ(morton.front(), 1.0);  // one bit an axis: 4 cells for 1536 elements
    EXPECT_EQ(morton.back(), 0.0);
    EXPECT_TRUE(std::is_sorted(morton.rbegin(), morton.rend()));
}
