// Reader of the thesis's text format; see readers.hpp for the format.
#include <limits>

#include "kernels/mesh/readers.hpp"
#include "kernels/mesh/text_scanner.hpp"

namespace suite::mesh {

namespace {

const char* const format_hint =
    "the format is '<N> vertices in the domain', a header line, N lines 'id x y', "
    "'<M> faces in the domain', a header line, M lines 'v0 v1 v2'";

bool is_count_line(const TextScanner& s, std::string_view word) { return s.size() >= 2 && s.field(1) == word; }

}  // namespace

Mesh read_text_mesh(std::string_view text, const std::string& name) {
    TextScanner s(text, name);
    Mesh m;
    m.dim = 2;
    if (!s.next()) s.fail_at(1, "the file is empty (an empty mesh); " + std::string(format_hint));
    if (!is_count_line(s, "vertices"))
        s.fail("expected '<N> vertices in the domain', found '" + s.shown() + "'; " + format_hint);
    const std::uint64_t nv = s.uint(0, "the vertex count");
    const std::size_t nv_line = s.line_number();
    if (nv == 0) s.fail("the mesh has no vertices (an empty mesh)");
    if (nv >= std::numeric_limits<std::uint32_t>::max()) s.fail("too many vertices: at most 4294967294");
    s.expect_line("a header line after the vertex count");
    // Counts come from the file: never reserve more than the file could hold.
    const std::size_t cap = std::min<std::uint64_t>(nv, s.bytes() / 4 + 1);
    m.x.reserve(cap);
    m.y.reserve(cap);
    for (std::uint64_t i = 0; i < nv; ++i) {
        if (!s.next())
            s.fail("the file ends here, after " + std::to_string(i) + " of the " + std::to_string(nv) +
                   " vertices that line " + std::to_string(nv_line) + " promised");
        if (is_count_line(s, "faces") || is_count_line(s, "elements"))
            s.fail("found the face count after " + std::to_string(i) + " vertices, but line " +
                   std::to_string(nv_line) + " promised " + std::to_string(nv) + ": is the vertex count right?");
        s.expect_fields(3, "a vertex: id x y");
        if (s.uint(0, "a vertex id") != i)
            s.fail("vertex id " + std::string(s.field(0)) + " where " + std::to_string(i) +
                   " was expected: vertices are listed in order 0, 1, 2, ...");
        m.x.push_back(s.real(1, "the x coordinate"));
        m.y.push_back(s.real(2, "the y coordinate"));
    }
    if (!s.next()) s.fail("the file ends here, but '<M> faces in the domain' should follow the vertices");
    if (!is_count_line(s, "faces") && !is_count_line(s, "elements")) {
        if (s.size() == 3)
            s.fail("another vertex line after the " + std::to_string(nv) + " vertices that line " +
                   std::to_string(nv_line) + " promised: is the vertex count right?");
        s.fail("expected '<M> faces in the domain', found '" + s.shown() + "'; " + format_hint);
    }
    const std::uint64_t ne = s.uint(0, "the face count");
    const std::size_t ne_line = s.line_number();
    if (ne == 0) s.fail("the mesh has no faces (an empty mesh)");
    if (ne >= (1ULL << 30)) s.fail("too many faces: at most 1073741823");
    s.expect_line("a header line after the face count");
    std::vector<std::uint32_t> lines;
    const std::size_t ecap = std::min<std::uint64_t>(ne, s.bytes() / 6 + 1);
    m.conn.reserve(3 * ecap);
    lines.reserve(ecap);
    for (std::uint64_t j = 0; j < ne; ++j) {
        if (!s.next())
            s.fail("the file ends here, after " + std::to_string(j) + " of the " + std::to_string(ne) +
                   " faces that line " + std::to_string(ne_line) + " promised");
        if (s.size() == 4) s.fail("a face with 4 vertex indices: this format holds triangles only (3 indices a line)");
        s.expect_fields(3, "a triangle: v0 v1 v2");
        for (std::size_t k = 0; k < 3; ++k) {
            const std::uint64_t v = s.uint(k, "a vertex index");
            if (v >= nv)
                s.fail("vertex index " + std::to_string(v) + " is out of range: the mesh has " + std::to_string(nv) +
                       " vertices (0.." + std::to_string(nv - 1) + ")");
            m.conn.push_back(static_cast<std::uint32_t>(v));
        }
        lines.push_back(static_cast<std::uint32_t>(s.line_number()));
    }
    if (s.next())
        s.fail("unexpected content after the " + std::to_string(ne) + " faces that line " + std::to_string(ne_line) +
               " promised: is the face count right?");
    check_read_mesh(m, lines, name, s.line_number());
    return m;
}

}  // namespace suite::mesh
