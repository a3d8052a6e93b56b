// The mesh readers: good files of each format are read (boundary entities skipped, sparse node
// tags, both .msh versions), the writers' output reads back exactly, and every kind of bad file
// is refused with "NAME:LINE: what is wrong" at the right line.
#include <gtest/gtest.h>

#include "kernels/mesh/generate.hpp"
#include "kernels/mesh/mesh_error.hpp"
#include "kernels/mesh/readers.hpp"
#include "kernels/mesh/writers.hpp"
#include "tests/kernels/mesh_fixtures.hpp"

using namespace suite::mesh;
using namespace suite::test;

namespace {

void expect_same(const Mesh& a, const Mesh& b) {
    EXPECT_EQ(a.dim, b.dim);
    EXPECT_EQ(a.x, b.x);
    EXPECT_EQ(a.y, b.y);
    EXPECT_EQ(a.z, b.z);
    EXPECT_EQ(a.conn, b.conn);
}

Mesh read(const MeshFixture& f) {
    return f.format == "text" ? read_text_mesh(f.text, f.name) : read_msh(f.text, f.name);
}

class BadMesh : public testing::TestWithParam<BadMeshCase> {};

}  // namespace

TEST(MeshRead, TextSquare) {
    const Mesh m = read(good_text());
    EXPECT_EQ(m.vertices(), 4u);
    EXPECT_EQ((m.conn), (std::vector<std::uint32_t>{0, 1, 2, 0, 2, 3}));
    EXPECT_EQ(m.y[2], 1.0);
}

TEST(MeshRead, Msh22SkipsPointsLinesAndOtherSections) {
    const Mesh m = read(good_msh22());
    EXPECT_EQ(m.dim, 2);
    EXPECT_EQ(m.vertices(), 5u);
    EXPECT_EQ((m.conn), (std::vector<std::uint32_t>{0, 1, 4, 1, 2, 4, 2, 3, 4, 3, 0, 4}));
    EXPECT_TRUE(m.z.empty());
}

TEST(MeshRead, Msh41BlocksAndParametricNodes) {
    const Mesh m = read(good_msh41());
    EXPECT_EQ(m.vertices(), 5u);
    EXPECT_EQ((m.conn), (std::vector<std::uint32_t>{0, 1, 4, 1, 2, 4, 2, 3, 4, 3, 0, 4}));
    EXPECT_EQ(m.x[4], 0.5);
}

TEST(MeshRead, SparseNodeTagsMapToIndices) {
    // Tags 10, 1000000, 7: too sparse for a dense table.
    const std::string text =
        "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n3\n10 0 0 0\n1000000 1 0 0\n7 0 1 0\n$EndNodes\n"
        "$Elements\n1\n1 2 0 7 10 1000000\n$EndElements\n";
    const Mesh m = read_msh(text, "sparse.msh");
    EXPECT_EQ((m.conn), (std::vector<std::uint32_t>{2, 0, 1}));
}

TEST(MeshRead, WritersReadBackExactly) {
    for (const Mesh& m : {refine_uniform(disk_mesh(2)), box_mesh(2, 1, 3)}) {
        for (const char* version : {"2.2", "4.1"}) {
            SCOPED_TRACE(std::string("msh ") + version + ", dim " + std::to_string(m.dim));
            expect_same(read_msh(msh_text(m, version), "round-trip.msh"), m);
        }
    }
    const Mesh m = disk_mesh(1);
    const std::string vtu = vtu_text(m, {{"visit", std::vector<std::int64_t>(m.elements(), 7)}});
    EXPECT_NE(vtu.find("NumberOfPoints=\"19\" NumberOfCells=\"24\""), std::string::npos);
    EXPECT_NE(vtu.find("Name=\"visit\""), std::string::npos);
    // A line per point, four per cell (corners, offset, type, visit), 23 lines of XML.
    EXPECT_EQ(std::count(vtu.begin(), vtu.end(), '\n'), 19 + 4 * 24 + 23);
    EXPECT_NE(vtu.find("\n72\n</DataArray>"), std::string::npos);  // the last offset: 24 cells * 3 corners
}

TEST_P(BadMesh, RefusedWithNameLineAndReason) {
    const BadMeshCase& c = GetParam();
    try {
        read(c.file);
        FAIL() << "accepted";
    } catch (const MeshError& e) {
        const std::string what = e.what(), where = c.file.name + ":" + std::to_string(c.line) + ": ";
        EXPECT_EQ(what.rfind(where, 0), 0u) << what;
        EXPECT_NE(what.find(c.expected), std::string::npos) << what;
        EXPECT_EQ(what.find('\n'), std::string::npos) << what;
    }
}

INSTANTIATE_TEST_SUITE_P(Cases, BadMesh, testing::ValuesIn(bad_mesh_cases()),
                         [](const auto& info) { return info.param.id; });
