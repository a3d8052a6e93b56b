// The mesh generators, uniform refinement, exact counts of --mesh specs, and the thesis's
// meshes in ../shared/meshes read and refined to the sizes its README states.
#include <gtest/gtest.h>

#include <omp.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <numbers>
#include <set>

#include "kernels/mesh/generate.hpp"
#include "kernels/mesh/mesh_error.hpp"
#include "kernels/mesh/mesh_spec.hpp"
#include "kernels/mesh/readers.hpp"

using namespace suite::mesh;

namespace {

const std::string shared_meshes = std::string(SUITE_SOURCE_DIR) + "/../shared/meshes";

// Edges counted independently of EdgeTable: a std::set of sorted corner pairs.
std::size_t count_edges(const Mesh& m) {
    std::set<std::pair<std::uint32_t, std::uint32_t>> edges;
    const int k = m.corners();
    for (std::size_t e = 0; e < m.elements(); ++e)
        for (int i = 0; i < k; ++i)
            for (int j = i + 1; j < k; ++j) {
                const auto a = m.conn[e * k + i], b = m.conn[e * k + j];
                edges.insert({std::min(a, b), std::max(a, b)});
            }
    return edges.size();
}

// How many vertices sit where another one already is: 0 when each shared midpoint was made once.
std::size_t duplicate_points(const Mesh& m) {
    std::vector<std::array<double, 3>> p;
    for (std::size_t v = 0; v < m.vertices(); ++v) p.push_back({m.x[v], m.y[v], m.dim == 3 ? m.z[v] : 0.0});
    std::sort(p.begin(), p.end());
    std::size_t same = 0;
    for (std::size_t i = 1; i < p.size(); ++i) same += p[i] == p[i - 1];
    return same;
}

// Every child has 1/4 (1/8) of its parent's signed measure: same orientation, the right split.
void expect_children_split_parent(const Mesh& parent, const Mesh& child) {
    const std::size_t per = parent.dim == 2 ? 4 : 8;
    ASSERT_EQ(child.elements(), per * parent.elements());
    for (std::size_t e = 0; e < parent.elements(); ++e) {
        const double whole = signed_measure(parent.view(), e);
        for (std::size_t c = 0; c < per; ++c)
            ASSERT_NEAR(signed_measure(child.view(), per * e + c), whole / static_cast<double>(per),
                        1e-12 * std::fabs(whole))
                << "child " << c << " of element " << e;
    }
}

}  // namespace

TEST(MeshGenerate, DiskCountsAreaAndBoundary) {
    double previous_gap = 0;
    for (int k = 0; k <= 5; ++k) {
        SCOPED_TRACE("refine=" + std::to_string(k));
        const Mesh m = disk_mesh(k);
        EXPECT_EQ(m.dim, 2);
        EXPECT_EQ(m.elements(), 6u << (2 * k));
        EXPECT_EQ(m.vertices(), mesh_counts(parse_mesh_spec("disk:refine=" + std::to_string(k))).vertices);
        double area = 0;
        for (std::size_t e = 0; e < m.elements(); ++e) {
            const double a = signed_measure(m.view(), e) / 2;
            ASSERT_GT(a, 0) << "triangle " << e << " is not counter-clockwise";
            area += a;
        }
        // The boundary (edges of one triangle only) lies on the unit circle, in 6 * 2^k edges.
        std::map<std::pair<std::uint32_t, std::uint32_t>, int> uses;
        for (std::size_t e = 0; e < m.elements(); ++e)
            for (int i = 0; i < 3; ++i) {
                const auto a = m.conn[3 * e + i], b = m.conn[3 * e + (i + 1) % 3];
                ++uses[{std::min(a, b), std::max(a, b)}];
            }
        std::size_t boundary = 0;
        for (const auto& [edge, n] : uses) {
            if (n != 1) continue;
            ++boundary;
            for (auto v : {edge.first, edge.second}) ASSERT_NEAR(std::hypot(m.x[v], m.y[v]), 1.0, 1e-12);
        }
        EXPECT_EQ(boundary, 6u << k);
        // An inscribed polygon: its area approaches pi from below, the gap shrinking ~4x a level.
        const double gap = std::numbers::pi - area;
        EXPECT_GT(gap, 0);
        if (k > 0) {
            EXPECT_LT(gap, previous_gap / 3.5);
        }
        previous_gap = gap;
    }
}

TEST(MeshGenerate, BoxCountsVolumeAndConformity) {
    const Mesh m = box_mesh(3, 2, 4);
    EXPECT_EQ(m.dim, 3);
    EXPECT_EQ(m.elements(), 6u * 3 * 2 * 4);
    EXPECT_EQ(m.vertices(), 4u * 3 * 5);
    double volume = 0;
    for (std::size_t e = 0; e < m.elements(); ++e) {
        const double v = signed_measure(m.view(), e) / 6;
        ASSERT_GT(v, 0) << "tetrahedron " << e << " is negatively oriented";
        volume += v;
    }
    EXPECT_NEAR(volume, 1.0, 1e-12);
    // Conforming: every face is shared by two tetrahedra except the boundary's 2 per square.
    std::map<std::array<std::uint32_t, 3>, int> faces;
    for (std::size_t e = 0; e < m.elements(); ++e)
        for (int skip = 0; skip < 4; ++skip) {
            std::array<std::uint32_t, 3> f{};
            for (int i = 0, n = 0; i < 4; ++i)
                if (i != skip) f[n++] = m.conn[4 * e + i];
            std::sort(f.begin(), f.end());
            ++faces[f];
        }
    std::size_t boundary = 0;
    for (const auto& [f, n] : faces) {
        ASSERT_LE(n, 2);
        boundary += n == 1;
    }
    EXPECT_EQ(boundary, 4u * (3 * 2 + 2 * 4 + 3 * 4));
    EXPECT_EQ(count_edges(m), m.vertices() + faces.size() - m.elements() - 1);  // Euler for a ball
}

TEST(MeshRefine, TrianglesTimesFourVerticesPlusEdgesMidpointsOnce) {
    const Mesh m = read_mesh_file(shared_meshes + "/unit_circle.txt");
    const Mesh r = refine_uniform(m);
    EXPECT_EQ(r.elements(), 4 * m.elements());
    EXPECT_EQ(r.vertices(), m.vertices() + count_edges(m));
    EXPECT_EQ(duplicate_points(r), 0u);
    expect_children_split_parent(m, r);
    // Old vertices keep their numbers and places; each new one is the midpoint of an old edge.
    for (std::size_t v = 0; v < m.vertices(); ++v) ASSERT_TRUE(r.x[v] == m.x[v] && r.y[v] == m.y[v]);
}

TEST(MeshRefine, TetrahedraTimesEightVerticesPlusEdgesMidpointsOnce) {
    const Mesh m = box_mesh(2, 3, 2);
    const Mesh r = refine_uniform(m);
    EXPECT_EQ(r.vertices(), m.vertices() + count_edges(m));
    EXPECT_EQ(duplicate_points(r), 0u);
    expect_children_split_parent(m, r);
    const Mesh rr = refine_uniform(r);
    expect_children_split_parent(r, rr);
    EXPECT_EQ(duplicate_points(rr), 0u);
    EXPECT_EQ(rr.vertices(), mesh_counts(parse_mesh_spec("box:2,3,2:refine=2")).vertices);
    EXPECT_EQ(rr.elements(), mesh_counts(parse_mesh_spec("box:2,3,2:refine=2")).elements);
}

TEST(MeshRefine, SameResultWithOneAndTwoThreads) {
    const Mesh m = box_mesh(3, 3, 3);
    const int saved = omp_get_max_threads();
    omp_set_num_threads(1);
    const Mesh a = refine_uniform(m);
    omp_set_num_threads(2);
    const Mesh b = refine_uniform(m);
    omp_set_num_threads(saved);
    EXPECT_EQ(a.conn, b.conn);
    EXPECT_EQ(a.x, b.x);
}

TEST(MeshShared, UnitCircleHasTheStatedCounts) {
    const Mesh m = read_mesh_file(shared_meshes + "/unit_circle.txt");
    EXPECT_EQ(m.dim, 2);
    EXPECT_EQ(m.vertices(), 1039u);
    EXPECT_EQ(m.elements(), 1976u);
    EXPECT_EQ(m.conn[0], 175u);  // the first face line: 175 625 473
    EXPECT_EQ(m.conn[2], 473u);
    EXPECT_DOUBLE_EQ(m.x[1], 0.998027);
}

TEST(MeshShared, FineCircleRefinedThreeTimesHasTheThesisCounts) {
    const MeshSpec spec = parse_mesh_spec("file:" + shared_meshes + "/unit_circle_fine.txt:refine=3");
    const Mesh m = load_mesh(spec);
    EXPECT_EQ(m.vertices(), 771185u);
    EXPECT_EQ(m.elements(), 1539968u);
    const MeshCounts c = mesh_counts(spec);
    EXPECT_EQ(c.vertices, 771185u);
    EXPECT_EQ(c.elements, 1539968u);
}

TEST(MeshSpecs, ParsedOrRefusedWithWhatIsAccepted) {
    EXPECT_EQ(parse_mesh_spec("disk:refine=3").refine, 3);
    const MeshSpec b = parse_mesh_spec("box:4,5,6:refine=1");
    EXPECT_EQ(b.nx * 100 + b.ny * 10 + b.nz, 456u);
    EXPECT_EQ(b.refine, 1);
    EXPECT_EQ(parse_mesh_spec("file:/a:b/c.msh:refine=2").path, "/a:b/c.msh");
    EXPECT_EQ(parse_mesh_spec("file:/a:b/c.msh").path, "/a:b/c.msh");
    for (const char* bad : {"disk", "disk:refine=x", "box:4,5", "box:0,1,1", "file:", "sphere:refine=2",
                            "disk:refine=31", "box:1,1,1:refine=-1"}) {
        try {
            parse_mesh_spec(bad);
            ADD_FAILURE() << bad << " was accepted";
        } catch (const suite::UsageError& e) {
            EXPECT_NE(std::string(e.what()).find("disk:refine=K"), std::string::npos) << e.what();
        }
    }
    EXPECT_THROW(mesh_counts(parse_mesh_spec("disk:refine=14")), suite::UsageError);  // over 2^30 elements
    EXPECT_EQ(mesh_counts(parse_mesh_spec("disk:refine=13")).elements, 6ULL << 26);
    EXPECT_EQ(disk_spec_for(1), "disk:refine=0");
    EXPECT_EQ(disk_spec_for(1536), "disk:refine=4");
    EXPECT_EQ(disk_spec_for(1537), "disk:refine=5");
}
