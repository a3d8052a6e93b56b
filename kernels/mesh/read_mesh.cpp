// What every reader shares: the final checks, and reading a file whole and picking its reader.
#include <sys/stat.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>

#include "kernels/mesh/mesh_error.hpp"
#include "kernels/mesh/readers.hpp"

namespace suite::mesh {

void check_read_mesh(const Mesh& m, const std::vector<std::uint32_t>& element_lines, const std::string& name, std::size_t last_line) {
    if (m.elements() == 0) throw MeshError(name, last_line, "the mesh has no elements (an empty mesh)");
    const MeshView v = m.view();
    for (std::size_t e = 0; e < m.elements(); ++e)
        if (degenerate(v, e))
            throw MeshError(name, element_lines[e], "a degenerate " + element_word(m.dim) + " (zero " + (m.dim == 2 ? "area" : "volume") +
                                                        " or a repeated vertex); every element must have a positive " +
                                                        (m.dim == 2 ? "area" : "volume"));
}

Mesh read_mesh_file(const std::string& path) {
    struct stat st{};
    if (stat(path.c_str(), &st) != 0) throw MeshError(path, 0, std::string("cannot open the mesh file: ") + std::strerror(errno));
    if (!S_ISREG(st.st_mode)) throw MeshError(path, 0, "not a regular file; give a mesh file (.msh or the thesis's .txt format)");
    std::ifstream in(path, std::ios::binary);
    if (!in) throw MeshError(path, 0, std::string("cannot open the mesh file: ") + std::strerror(errno));
    std::ostringstream buf;
    buf << in.rdbuf();
    if (in.bad()) throw MeshError(path, 0, std::string("cannot read the mesh file: ") + std::strerror(errno));
    const std::string text = buf.str();
    const std::size_t first = text.find_first_not_of(" \t\r\n");
    if (first != std::string::npos && text.compare(first, 11, "$MeshFormat") == 0) return read_msh(text, path);
    return read_text_mesh(text, path);
}

}  // namespace suite::mesh
