// Reader of Gmsh .msh ASCII files, versions 2.2 and 4.1; see readers.hpp for what is kept.
#include <algorithm>
#include <limits>
#include <map>

#include "kernels/mesh/readers.hpp"
#include "kernels/mesh/text_scanner.hpp"

namespace suite::mesh {

namespace {

struct ElementType {
    int dim;
    int nodes;
    const char* name;
};

// Gmsh's element types 1..19 (the ones of order 1 and 2); others are refused by number.
const ElementType* element_type(std::int64_t t) {
    static const ElementType types[] = {
        {1, 2, "2-node line"},        {2, 3, "3-node triangle"},      {2, 4, "4-node quadrangle"},
        {3, 4, "4-node tetrahedron"}, {3, 8, "8-node hexahedron"},    {3, 6, "6-node prism"},
        {3, 5, "5-node pyramid"},     {1, 3, "3-node line"},          {2, 6, "6-node triangle"},
        {2, 9, "9-node quadrangle"},  {3, 10, "10-node tetrahedron"}, {3, 27, "27-node hexahedron"},
        {3, 18, "18-node prism"},     {3, 14, "14-node pyramid"},     {0, 1, "point"},
        {2, 8, "8-node quadrangle"},  {3, 20, "20-node hexahedron"},  {3, 15, "15-node prism"},
        {3, 13, "13-node pyramid"},
    };
    return t >= 1 && t <= 19 ? &types[t - 1] : nullptr;
}

const char* const accepted_types =
    "accepted: type 2 (3-node triangle) or type 4 (4-node tetrahedron), with points and lines "
    "(and triangles in a 3D mesh) as boundary entities, which are ignored";

// Everything read, before the element dimension is known.
struct Raw {
    std::vector<std::uint64_t> node_tags;
    std::vector<std::uint32_t> node_lines;
    Mesh nodes;  // x, y, z of every node; conn unused
    bool have_nodes = false, have_elements = false;
    std::vector<std::uint64_t> corner_tags[2];  // [0]: triangles, [1]: tetrahedra
    std::vector<std::uint32_t> element_lines[2];
    std::map<std::int64_t, std::size_t> first_line_of_type;  // every type met, with its first line
    std::size_t elements_line = 0;
};

void reserve_nodes(Raw& r, std::uint64_t n, std::size_t bytes) {
    const std::size_t cap = std::min<std::uint64_t>(n, bytes / 8 + 1);
    r.node_tags.reserve(cap);
    r.node_lines.reserve(cap);
    r.nodes.x.reserve(cap);
    r.nodes.y.reserve(cap);
    r.nodes.z.reserve(cap);
}

void add_node(Raw& r, const TextScanner& s, std::uint64_t tag, std::size_t first_coordinate) {
    if (tag == 0) s.fail("node tag 0: Gmsh node tags start at 1");
    r.node_tags.push_back(tag);
    r.node_lines.push_back(static_cast<std::uint32_t>(s.line_number()));
    r.nodes.x.push_back(s.real(first_coordinate, "the x coordinate"));
    r.nodes.y.push_back(s.real(first_coordinate + 1, "the y coordinate"));
    r.nodes.z.push_back(s.real(first_coordinate + 2, "the z coordinate"));
}

// One element line's type and corner tags, starting at field `first_node`.
void add_element(Raw& r, const TextScanner& s, std::int64_t type, std::size_t first_node) {
    const ElementType* t = element_type(type);
    if (!t) s.fail("unknown element type " + std::to_string(type) + "; " + accepted_types);
    r.first_line_of_type.emplace(type, s.line_number());
    if (type != 2 && type != 4) return;  // kept only if it turns out to be of the mesh's type
    const int which = type == 2 ? 0 : 1;
    for (int k = 0; k < t->nodes; ++k)
        r.corner_tags[which].push_back(s.uint(first_node + static_cast<std::size_t>(k), "a node tag"));
    r.element_lines[which].push_back(static_cast<std::uint32_t>(s.line_number()));
}

void expect_end(TextScanner& s, const std::string& section, const std::string& counted, std::size_t count_line) {
    s.expect_line("$End" + section);
    if (s.field(0) != "$End" + section)
        s.fail("expected $End" + section + ", found '" + s.shown() + "': is the " + counted + " count on line " +
               std::to_string(count_line) + " right?");
}

// A line where a node or an element was expected: a section end there means a count too large.
void refuse_early_end(const TextScanner& s, const std::string& what, std::uint64_t got, std::uint64_t promised,
                      std::size_t count_line) {
    if (s.field(0).substr(0, 1) == "$")
        s.fail("found '" + s.shown() + "' after " + std::to_string(got) + " of the " + std::to_string(promised) + " " +
               what + " that line " + std::to_string(count_line) + " promised: is the count right?");
}

void nodes_v2(TextScanner& s, Raw& r) {
    s.expect_line("the node count");
    s.expect_fields(1, "the node count");
    const std::uint64_t n = s.uint(0, "the node count");
    const std::size_t count_line = s.line_number();
    reserve_nodes(r, n, s.bytes());
    for (std::uint64_t i = 0; i < n; ++i) {
        s.expect_line("node " + std::to_string(i + 1) + " of " + std::to_string(n));
        refuse_early_end(s, "nodes", i, n, count_line);
        s.expect_fields(4, "a node: tag x y z");
        add_node(r, s, s.uint(0, "a node tag"), 1);
    }
    expect_end(s, "Nodes", "node", count_line);
}

void elements_v2(TextScanner& s, Raw& r) {
    s.expect_line("the element count");
    s.expect_fields(1, "the element count");
    const std::uint64_t n = s.uint(0, "the element count");
    const std::size_t count_line = s.line_number();
    for (std::uint64_t i = 0; i < n; ++i) {
        s.expect_line("element " + std::to_string(i + 1) + " of " + std::to_string(n));
        refuse_early_end(s, "elements", i, n, count_line);
        if (s.size() < 3) s.fail("expected 'tag type ntags tags... nodes...', found '" + s.shown() + "'");
        const std::int64_t type = s.sint(1, "the element type");
        const ElementType* t = element_type(type);
        if (!t) s.fail("unknown element type " + std::to_string(type) + "; " + accepted_types);
        const std::uint64_t ntags = s.uint(2, "the number of tags");
        // Compared as counts, never by computing 3 + ntags + nodes, which a huge ntags overflows.
        if (ntags > s.size())
            s.fail("the element declares " + std::to_string(ntags) + " tags and the line has only " +
                   std::to_string(s.size()) + " fields; a " + std::string(t->name) + " needs 3 + tags + " +
                   std::to_string(t->nodes) + " node fields");
        if (s.size() != 3 + ntags + static_cast<std::uint64_t>(t->nodes))
            s.fail("a " + std::string(t->name) + " with " + std::to_string(ntags) + " tags needs " +
                   std::to_string(3 + ntags + t->nodes) + " fields, found " + std::to_string(s.size()));
        if (ntags > 64) s.fail("the element declares " + std::to_string(ntags) + " tags; at most 64 are accepted");
        add_element(r, s, type, 3 + static_cast<std::size_t>(ntags));
    }
    expect_end(s, "Elements", "element", count_line);
}

void nodes_v4(TextScanner& s, Raw& r) {
    s.expect_line("'numEntityBlocks numNodes minNodeTag maxNodeTag'");
    s.expect_fields(4, "numEntityBlocks numNodes minNodeTag maxNodeTag");
    const std::uint64_t blocks = s.uint(0, "the number of entity blocks"), n = s.uint(1, "the node count");
    const std::size_t count_line = s.line_number();
    reserve_nodes(r, n, s.bytes());
    std::uint64_t seen = 0;
    std::vector<std::uint64_t> tags;
    std::vector<std::uint32_t> tag_lines;
    for (std::uint64_t b = 0; b < blocks; ++b) {
        s.expect_line("a node block header 'entityDim entityTag parametric numNodesInBlock'");
        refuse_early_end(s, "node blocks", b, blocks, count_line);
        s.expect_fields(4, "entityDim entityTag parametric numNodesInBlock");
        const std::uint64_t edim = s.uint(0, "the entity dimension"), parametric = s.uint(2, "the parametric flag");
        const std::uint64_t m = s.uint(3, "the number of nodes in the block");
        if (edim > 3 || parametric > 1)
            s.fail("expected an entity dimension 0..3 and a parametric flag 0 or 1, found '" + s.shown() + "'");
        if (m > n - seen)
            s.fail("this block holds " + std::to_string(m) + " nodes, more than the " + std::to_string(n - seen) +
                   " left of the " + std::to_string(n) + " that line " + std::to_string(count_line) + " promised");
        tags.clear();
        tag_lines.clear();
        for (std::uint64_t i = 0; i < m; ++i) {
            s.expect_line("the tag of node " + std::to_string(i + 1) + " of the block");
            s.expect_fields(1, "a node tag");
            tags.push_back(s.uint(0, "a node tag"));
        }
        const std::size_t fields = 3 + (parametric ? edim : 0);  // u, (u v), (u v w) after x y z
        for (std::uint64_t i = 0; i < m; ++i) {
            s.expect_line("the coordinates of node " + std::to_string(i + 1) + " of the block");
            s.expect_fields(fields, parametric ? "x y z and parametric coordinates" : "x y z");
            add_node(r, s, tags[i], 0);
        }
        seen += m;
    }
    if (seen != n)
        s.fail("the node blocks hold " + std::to_string(seen) + " nodes, but line " + std::to_string(count_line) +
               " promised " + std::to_string(n));
    expect_end(s, "Nodes", "node", count_line);
}

void elements_v4(TextScanner& s, Raw& r) {
    s.expect_line("'numEntityBlocks numElements minElementTag maxElementTag'");
    s.expect_fields(4, "numEntityBlocks numElements minElementTag maxElementTag");
    const std::uint64_t blocks = s.uint(0, "the number of entity blocks"), n = s.uint(1, "the element count");
    const std::size_t count_line = s.line_number();
    std::uint64_t seen = 0;
    for (std::uint64_t b = 0; b < blocks; ++b) {
        s.expect_line("an element block header 'entityDim entityTag elementType numElementsInBlock'");
        refuse_early_end(s, "element blocks", b, blocks, count_line);
        s.expect_fields(4, "entityDim entityTag elementType numElementsInBlock");
        const std::int64_t type = s.sint(2, "the element type");
        const ElementType* t = element_type(type);
        if (!t) s.fail("unknown element type " + std::to_string(type) + "; " + accepted_types);
        const std::uint64_t m = s.uint(3, "the number of elements in the block");
        const std::size_t block_line = s.line_number();
        if (m > n - seen)
            s.fail("this block holds " + std::to_string(m) + " elements, more than the " + std::to_string(n - seen) +
                   " left of the " + std::to_string(n) + " that line " + std::to_string(count_line) + " promised");
        for (std::uint64_t i = 0; i < m; ++i) {
            s.expect_line("element " + std::to_string(i + 1) + " of the block");
            refuse_early_end(s, "elements of the block", i, m, block_line);
            s.expect_fields(1 + static_cast<std::size_t>(t->nodes),
                            "an element tag and the " + std::string(t->name) + "'s node tags");
            add_element(r, s, type, 1);
        }
        seen += m;
    }
    if (seen != n)
        s.fail("the element blocks hold " + std::to_string(seen) + " elements, but line " + std::to_string(count_line) +
               " promised " + std::to_string(n));
    expect_end(s, "Elements", "element", count_line);
}

// Node tag -> index: a dense table when the tags are dense (the usual case), else a sorted list.
class TagIndex {
public:
    TagIndex(const Raw& r, const TextScanner& s) {
        const auto& tags = r.node_tags;
        std::uint64_t max_tag = 0;
        for (auto t : tags) max_tag = std::max(max_tag, t);
        dense_ = max_tag <= 8 * tags.size() + 1024;
        if (dense_) {
            table_.assign(max_tag + 1, none);
            for (std::size_t i = 0; i < tags.size(); ++i) {
                if (table_[tags[i]] != none)
                    s.fail_at(r.node_lines[i], "node tag " + std::to_string(tags[i]) + " is defined twice");
                table_[tags[i]] = static_cast<std::uint32_t>(i);
            }
        } else {
            sorted_.reserve(tags.size());
            for (std::size_t i = 0; i < tags.size(); ++i) sorted_.push_back({tags[i], static_cast<std::uint32_t>(i)});
            std::sort(sorted_.begin(), sorted_.end());
            for (std::size_t i = 1; i < sorted_.size(); ++i)
                if (sorted_[i].first == sorted_[i - 1].first)
                    s.fail_at(r.node_lines[std::max(sorted_[i].second, sorted_[i - 1].second)],
                              "node tag " + std::to_string(sorted_[i].first) + " is defined twice");
        }
    }
    std::uint32_t find(std::uint64_t tag) const {
        if (dense_) return tag < table_.size() ? table_[tag] : none;
        auto it = std::lower_bound(sorted_.begin(), sorted_.end(), std::pair<std::uint64_t, std::uint32_t>{tag, 0});
        return it != sorted_.end() && it->first == tag ? it->second : none;
    }
    static constexpr std::uint32_t none = std::numeric_limits<std::uint32_t>::max();

private:
    bool dense_ = true;
    std::vector<std::uint32_t> table_;
    std::vector<std::pair<std::uint64_t, std::uint32_t>> sorted_;
};

Mesh assemble(const Raw& r, const TextScanner& s) {
    int top = -1;
    for (const auto& [type, line] : r.first_line_of_type) top = std::max(top, element_type(type)->dim);
    if (top < 2)
        s.fail_at(r.elements_line, std::string("the mesh has no triangles or tetrahedra") +
                                       (top < 0 ? " (an empty mesh)" : " (only points and lines)"));
    const int keep = top == 2 ? 2 : 4;
    for (const auto& [type, line] : r.first_line_of_type) {
        if (type == keep || element_type(type)->dim != top) continue;
        if (r.first_line_of_type.count(keep))
            s.fail_at(std::max(line, r.first_line_of_type.at(keep)),
                      std::string("mixed element types: ") + element_type(keep)->name + "s (line " +
                          std::to_string(r.first_line_of_type.at(keep)) + ") and " + element_type(type)->name +
                          "s (line " + std::to_string(line) + "); " + accepted_types);
        s.fail_at(line, "element type " + std::to_string(type) + " (" + element_type(type)->name +
                            ") is not supported; " + accepted_types);
    }
    Mesh m;
    m.dim = top;
    m.x = r.nodes.x;
    m.y = r.nodes.y;
    if (top == 3)
        m.z = r.nodes.z;
    else
        for (std::size_t i = 0; i < r.nodes.z.size(); ++i)
            if (r.nodes.z[i] != 0)
                s.fail_at(r.node_lines[i], "a node with z = " + std::to_string(r.nodes.z[i]) +
                                               " in a mesh of triangles: a 2D mesh must lie in the plane z = 0");
    const TagIndex index(r, s);
    const int which = top == 2 ? 0 : 1;
    const auto& tags = r.corner_tags[which];
    const auto& lines = r.element_lines[which];
    m.conn.resize(tags.size());
    for (std::size_t i = 0; i < tags.size(); ++i) {
        const std::uint32_t v = index.find(tags[i]);
        if (v == TagIndex::none)
            s.fail_at(
                lines[i / static_cast<std::size_t>(m.corners())],
                "node tag " + std::to_string(tags[i]) + " is out of range: no node with that tag is defined in $Nodes");
        m.conn[i] = v;
    }
    check_read_mesh(m, lines, s.name(), s.line_number());
    return m;
}

}  // namespace

Mesh read_msh(std::string_view text, const std::string& name) {
    TextScanner s(text, name);
    if (!s.next()) s.fail_at(1, "the file is empty (an empty mesh); a .msh file starts with $MeshFormat");
    if (s.field(0) != "$MeshFormat") s.fail("a .msh file starts with $MeshFormat, found '" + s.shown() + "'");
    s.expect_line("the format line 'version file-type data-size'");
    s.expect_fields(3, "version file-type data-size");
    const std::string version(s.field(0));
    if (version != "2.2" && version != "4.1")
        s.fail(".msh version " + version + " is not supported; accepted: 2.2 and 4.1 (ASCII)");
    if (s.field(1) != "0")
        s.fail("a binary .msh file (file-type " + std::string(s.field(1)) +
               "); only ASCII (file-type 0) is read: save it with Mesh.Binary = 0");
    expect_end(s, "MeshFormat", "format", s.line_number());
    Raw r;
    while (s.next()) {
        const std::string section(s.field(0));
        if (section.empty() || section[0] != '$' || s.size() != 1)
            s.fail("expected a section such as $Nodes or $Elements, found '" + s.shown() + "'");
        if (section == "$Nodes") {
            if (r.have_nodes) s.fail("a second $Nodes section; the suite reads files with one");
            version == "2.2" ? nodes_v2(s, r) : nodes_v4(s, r);
            r.have_nodes = true;
        } else if (section == "$Elements") {
            if (!r.have_nodes) s.fail("$Elements before $Nodes");
            if (r.have_elements) s.fail("a second $Elements section; the suite reads files with one");
            r.elements_line = s.line_number();
            version == "2.2" ? elements_v2(s, r) : elements_v4(s, r);
            r.have_elements = true;
        } else {
            // Other sections ($PhysicalNames, $Entities, $NodeData, ...) carry nothing the suite uses.
            const std::size_t start = s.line_number();
            const std::string end = "$End" + section.substr(1);
            bool closed = false;
            while (!closed && s.next()) closed = s.field(0) == end;
            if (!closed)
                s.fail("the section " + section + " that starts on line " + std::to_string(start) + " has no " + end);
        }
    }
    if (!r.have_nodes || !r.have_elements)
        s.fail(std::string("the file ends without a ") + (r.have_nodes ? "$Elements" : "$Nodes") +
               " section (an empty mesh)");
    return assemble(r, s);
}

}  // namespace suite::mesh
