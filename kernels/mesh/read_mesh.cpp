// What every reader shares: the final checks, and reading a file whole and picking its reader.
#include <sys/stat.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <sstream>

#include "harness/common/input_file.hpp"
#include "kernels/mesh/mesh_error.hpp"
#include "kernels/mesh/readers.hpp"

namespace suite::mesh {

void check_read_mesh(const Mesh& m, const std::vector<std::uint32_t>& element_lines, const std::string& name,
                     std::size_t last_line) {
    if (m.elements() == 0) throw MeshError(name, last_line, "the mesh has no elements (an empty mesh)");
    const MeshView v = m.view();
    for (std::size_t e = 0; e < m.elements(); ++e)
        if (degenerate(v, e))
            throw MeshError(name, element_lines[e],
                            "a degenerate " + element_word(m.dim) + " (zero " + (m.dim == 2 ? "area" : "volume") +
                                " or a repeated vertex); every element must have a positive " +
                                (m.dim == 2 ? "area" : "volume"));
    // An element listed twice: its corners, in any order, are another element's. (Sorted by
    // corner set, ties by position, so the message names the later line and the earlier one.)
    const std::size_t k = static_cast<std::size_t>(m.corners());
    std::vector<std::pair<std::array<std::uint32_t, 4>, std::uint32_t>> keys(m.elements());
    for (std::size_t e = 0; e < m.elements(); ++e) {
        // A triangle's fourth slot holds the largest value, which sorts last and matches.
        std::array<std::uint32_t, 4> c{UINT32_MAX, UINT32_MAX, UINT32_MAX, UINT32_MAX};
        for (std::size_t j = 0; j < k; ++j) c[j] = m.conn[e * k + j];
        std::sort(c.begin(), c.end());
        keys[e] = {c, static_cast<std::uint32_t>(e)};
    }
    std::sort(keys.begin(), keys.end());
    for (std::size_t i = 1; i < keys.size(); ++i)
        if (keys[i].first == keys[i - 1].first) {
            const std::uint32_t later = keys[i].second, earlier = keys[i - 1].second;
            std::string corners;
            for (std::size_t c = 0; c < k; ++c) {
                if (c) corners += ' ';
                corners += std::to_string(m.conn[later * k + c]);
            }
            throw MeshError(name, element_lines[later],
                            "the " + element_word(m.dim) + " " + corners + " again: line " +
                                std::to_string(element_lines[earlier]) + " has the same corners; every element once");
        }
}

Mesh read_mesh_file(const std::string& path) {
    const InputText in = read_regular_file(path, 1ULL << 32);
    if (!in.ok) throw MeshError(path, 0, in.reason + "; give a mesh file (.msh or the thesis's .txt format)");
    const std::string& text = in.text;
    const std::size_t first = text.find_first_not_of(" \t\r\n");
    if (first != std::string::npos && text.compare(first, 11, "$MeshFormat") == 0) return read_msh(text, path);
    return read_text_mesh(text, path);
}

}  // namespace suite::mesh
