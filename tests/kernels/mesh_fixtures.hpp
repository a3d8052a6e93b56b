#pragma once
// Small mesh files, good and bad, shared by the reader tests and the end-to-end tests of the
// binary: each bad one says at which line the reader must complain, and with what words.
#include <ostream>
#include <string>
#include <vector>

namespace suite::test {

struct MeshFixture {
    std::string format;  // "text" or "msh"
    std::string name;    // file name, as messages show it
    std::string text;
};

// A unit square in two counter-clockwise triangles, in the thesis's format.
inline MeshFixture good_text() {
    return {
        "text", "square.txt",
        " 4 vertices in the domain\n Index of vertex | x coordinate | y coordinate\n 0 0 0\n 1 1 0\n 2 1 1\n 3 0 1\n"
        " 2 faces in the domain\n index of vertex 0 | index of vertex 1 | index of vertex 2\n 0 1 2\n 0 2 3\n"};
}

// A square around a centre node, with a point, 3 boundary lines and a $PhysicalNames section.
inline MeshFixture good_msh22() {
    return {"msh", "square22.msh",
            "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n1\n2 1 \"domain\"\n$EndPhysicalNames\n"
            "$Nodes\n5\n1 0 0 0\n2 1 0 0\n3 1 1 0\n4 0 1 0\n5 0.5 0.5 0\n$EndNodes\n"
            "$Elements\n8\n1 15 2 0 1 1\n2 1 2 0 1 1 2\n3 1 2 0 2 2 3\n4 1 2 0 3 3 4\n"
            "5 2 2 1 1 1 2 5\n6 2 2 1 1 2 3 5\n7 2 2 1 1 3 4 5\n8 2 2 1 1 4 1 5\n$EndElements\n"};
}

// The same square in 4.1: two node blocks (one parametric), a point block and a triangle block.
inline MeshFixture good_msh41() {
    return {"msh", "square41.msh",
            "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Entities\n1 0 0 1\n1 0 0 0 0\n1 0 0 0 1 1 0 0 0\n$EndEntities\n"
            "$Nodes\n2 5 1 5\n0 1 0 1\n1\n0 0 0\n2 1 1 4\n2\n3\n4\n5\n1 0 0 0.1 0.2\n1 1 0 0.3 0.4\n0 1 0 0.5 0.6\n0.5 "
            "0.5 0 0.7 0.8\n$EndNodes\n"
            "$Elements\n2 5 1 5\n0 1 15 1\n1 1\n2 1 2 4\n2 1 2 5\n3 2 3 5\n4 3 4 5\n5 4 1 5\n$EndElements\n"};
}

struct BadMeshCase {
    std::string id;
    MeshFixture file;
    std::size_t line;      // where the reader must point
    std::string expected;  // words the message must hold
};
// gtest shows a case by its id.
inline void PrintTo(const BadMeshCase& c, std::ostream* os) { *os << c.id; }

// The good text with `line` (1-based) replaced by `with` ("" removes it), or cut after it.
inline std::string edit_lines(const std::string& text, std::size_t line, const std::string& with,
                              bool cut_after = false) {
    std::vector<std::string> lines;
    std::size_t at = 0;
    while (at < text.size()) {
        const auto end = text.find('\n', at);
        lines.push_back(text.substr(at, end - at));
        at = end + 1;
    }
    std::string out;
    for (std::size_t i = 0; i < lines.size(); ++i) {
        if (i + 1 == line && !cut_after) {
            if (!with.empty()) out += with + "\n";
            continue;
        }
        out += lines[i] + "\n";
        if (i + 1 == line && cut_after) break;
    }
    return out;
}

inline std::vector<BadMeshCase> bad_mesh_cases() {
    const std::string t = good_text().text, m = good_msh22().text, f = good_msh41().text;
    auto text = [](std::string name, std::string s) { return MeshFixture{"text", name, std::move(s)}; };
    auto msh = [](std::string name, std::string s) { return MeshFixture{"msh", name, std::move(s)}; };
    std::string tags65;  // a line with every field its 65 tags need
    for (int i = 0; i < 65; ++i) tags65 += " 1";
    return {
        // The thesis's text format.
        {"TextTruncatedInVertices", text("a.txt", edit_lines(t, 4, "", true)), 4,
         "ends here, after 2 of the 4 vertices"},
        {"TextTruncatedInFaces", text("b.txt", edit_lines(t, 9, "", true)), 9, "ends here, after 1 of the 2 faces"},
        {"TextVertexCountTooLarge", text("c.txt", edit_lines(t, 1, " 5 vertices in the domain")), 7,
         "is the vertex count right?"},
        {"TextVertexCountTooSmall", text("d.txt", edit_lines(t, 1, " 3 vertices in the domain")), 6,
         "is the vertex count right?"},
        {"TextFaceCountTooSmall", text("e.txt", edit_lines(t, 7, " 1 faces in the domain")), 10,
         "is the face count right?"},
        {"TextIndexOutOfRange", text("f.txt", edit_lines(t, 10, " 0 2 4")), 10, "vertex index 4 is out of range"},
        {"TextNanCoordinate", text("g.txt", edit_lines(t, 5, " 2 nan 1")), 5, "not a finite number"},
        {"TextInfCoordinate", text("h.txt", edit_lines(t, 6, " 3 0 -inf")), 6, "not a finite number"},
        {"TextHugeCoordinate", text("i.txt", edit_lines(t, 6, " 3 0 1e999")), 6, "not a finite number"},
        {"TextRepeatedVertex", text("j.txt", edit_lines(t, 9, " 0 1 1")), 9, "degenerate triangle"},
        {"TextCollinearVertices", text("k.txt", edit_lines(t, 6, " 3 2 2")), 10, "zero area"},
        {"TextQuadrilateral", text("l.txt", edit_lines(t, 10, " 0 1 2 3")), 10, "triangles only"},
        {"TextEmptyFile", text("m.txt", ""), 1, "empty mesh"},
        {"TextNoVertices", text("n.txt", " 0 vertices in the domain\n"), 1, "empty mesh"},
        {"TextNoFaces", text("o.txt", edit_lines(t, 7, " 0 faces in the domain", false)), 7, "empty mesh"},
        {"TextVertexIdOutOfOrder", text("p.txt", edit_lines(t, 4, " 7 1 0")), 4, "vertex id 7 where 1 was expected"},
        {"TextNotANumber", text("q.txt", edit_lines(t, 4, " 1 one 0")), 4, "must be a number"},
        {"TextDuplicateTriangle", text("r.txt", edit_lines(t, 10, " 2 0 1")), 10,
         "the triangle 2 0 1 again: line 9 has the same corners"},
        // Gmsh 2.2.
        {"Msh22Truncated", msh("a.msh", edit_lines(m, 23, "", true)), 23, "element 7 of 8"},
        {"Msh22NodeCountTooLarge", msh("b.msh", edit_lines(m, 9, "6")), 15, "after 5 of the 6 nodes"},
        {"Msh22NodeCountTooSmall", msh("c.msh", edit_lines(m, 9, "4")), 14, "expected $EndNodes"},
        {"Msh22NodeOutOfRange", msh("d.msh", edit_lines(m, 25, "8 2 2 1 1 4 9 5")), 25, "node tag 9 is out of range"},
        {"Msh22NanCoordinate", msh("e.msh", edit_lines(m, 12, "3 1 NaN 0")), 12, "not a finite number"},
        {"Msh22Degenerate", msh("f.msh", edit_lines(m, 22, "5 2 2 1 1 1 2 2")), 22, "degenerate triangle"},
        {"Msh22DuplicateTriangle", msh("r.msh", edit_lines(m, 23, "6 2 2 1 1 2 5 1")), 23,
         "again: line 22 has the same corners"},
        {"Msh22MixedTypes", msh("g.msh", edit_lines(m, 25, "8 3 2 1 1 1 2 3 4")), 25, "mixed element types"},
        {"Msh22OnlyLines",
         msh("h.msh",
             edit_lines(edit_lines(edit_lines(edit_lines(edit_lines(m, 25, ""), 24, ""), 23, ""), 22, ""), 17, "4")),
         16, "no triangles or tetrahedra"},
        {"Msh22NotPlanar", msh("i.msh", edit_lines(m, 14, "5 0.5 0.5 0.1")), 14, "plane z = 0"},
        {"Msh22Binary", msh("j.msh", edit_lines(m, 2, "2.2 1 8")), 2, "binary"},
        {"Msh22Version", msh("k.msh", edit_lines(m, 2, "3.0 0 8")), 2, "accepted: 2.2 and 4.1"},
        {"Msh22DuplicateTag", msh("l.msh", edit_lines(m, 11, "1 1 0 0")), 11, "node tag 1 is defined twice"},
        {"Msh22UnknownType", msh("m.msh", edit_lines(m, 25, "8 99 2 1 1 4 1 5")), 25, "unknown element type 99"},
        {"Msh22OnlyQuads",
         msh("n.msh",
             "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n4\n1 0 0 0\n2 1 0 0\n3 1 1 0\n4 0 1 0\n$EndNodes\n"
             "$Elements\n1\n1 3 0 1 2 3 4\n$EndElements\n"),
         13, "is not supported"},
        {"Msh22HugeTagCount", msh("p.msh", edit_lines(m, 25, "8 2 200000000 1 1 4 1 5")), 25,
         "declares 200000000 tags and the line has only 8 fields"},
        {"Msh22TooManyTags", msh("q.msh", edit_lines(m, 25, "8 2 65" + tags65 + " 4 1 5")), 25,
         "declares 65 tags; at most 64"},
        {"Msh22UnclosedSection", msh("o.msh", m.substr(0, m.find("$EndPhysicalNames"))), 6, "has no $EndPhysicalNames"},
        // Gmsh 4.1.
        {"Msh41Truncated", msh("a41.msh", edit_lines(f, 30, "", true)), 30, "element 3 of the block"},
        {"Msh41NodeCountWrong", msh("b41.msh", edit_lines(f, 10, "2 6 1 6")), 22, "promised 6"},
        {"Msh41BlockTooLarge", msh("c41.msh", edit_lines(f, 28, "2 1 2 6")), 28, "more than the 4 left"},
        {"Msh41NodeOutOfRange", msh("d41.msh", edit_lines(f, 32, "5 4 1 6")), 32, "node tag 6 is out of range"},
        {"Msh41InfCoordinate", msh("e41.msh", edit_lines(f, 19, "1 inf 0 0.1 0.2")), 19, "not a finite number"},
        {"Msh41MissingParametric", msh("f41.msh", edit_lines(f, 19, "1 0 0")), 19, "expected 5 fields"},
        {"Msh41MixedTypes",
         msh("g41.msh", edit_lines(edit_lines(edit_lines(f, 32, "2 2 3 1\n5 1 2 3 4"), 28, "2 1 2 3"), 25, "3 5 1 5")),
         33, "mixed element types"},
        {"Msh41EmptyFile", msh("h41.msh", ""), 1, "empty mesh"},
        {"Msh41NoElementsSection", msh("i41.msh", f.substr(0, f.find("$Elements"))), 23, "without a $Elements section"},
    };
}

}  // namespace suite::test
