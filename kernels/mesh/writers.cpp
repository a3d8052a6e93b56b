#include "kernels/mesh/writers.hpp"

#include <charconv>
#include <stdexcept>

namespace suite::mesh {

namespace {

void put(std::string& out, double v) {
    char buf[32];
    auto [p, ec] = std::to_chars(buf, buf + sizeof buf, v);
    out.append(buf, p);
}
void put(std::string& out, std::uint64_t v) {
    char buf[24];
    auto [p, ec] = std::to_chars(buf, buf + sizeof buf, v);
    out.append(buf, p);
}
void put_point(std::string& out, const Mesh& m, std::size_t v) {
    put(out, m.x[v]);
    out += ' ';
    put(out, m.y[v]);
    out += ' ';
    put(out, m.dim == 3 ? m.z[v] : 0.0);
}

}  // namespace

std::string msh_text(const Mesh& m, const std::string& version) {
    if (version != "2.2" && version != "4.1") throw std::invalid_argument("msh version must be 2.2 or 4.1");
    const std::size_t nv = m.vertices(), ne = m.elements();
    const int k = m.corners(), type = m.dim == 2 ? 2 : 4;
    std::string out = "$MeshFormat\n" + version + " 0 8\n$EndMeshFormat\n$Nodes\n";
    out.reserve(nv * 60 + ne * 40);
    if (version == "2.2") {
        put(out, std::uint64_t{nv});
        out += '\n';
        for (std::size_t v = 0; v < nv; ++v) {
            put(out, std::uint64_t{v + 1});
            out += ' ';
            put_point(out, m, v);
            out += '\n';
        }
        out += "$EndNodes\n$Elements\n";
        put(out, std::uint64_t{ne});
        out += '\n';
        for (std::size_t e = 0; e < ne; ++e) {
            put(out, std::uint64_t{e + 1});
            out += ' ' + std::to_string(type) + " 2 1 1";  // physical and elementary tags
            for (int i = 0; i < k; ++i) {
                out += ' ';
                put(out, std::uint64_t{m.conn[e * k + i] + 1ULL});
            }
            out += '\n';
        }
        return out + "$EndElements\n";
    }
    // 4.1: one entity (the domain, of the mesh's dimension) holds every node and element.
    out += "1 " + std::to_string(nv) + " 1 " + std::to_string(nv) + "\n" + std::to_string(m.dim) + " 1 0 " +
           std::to_string(nv) + "\n";
    for (std::size_t v = 0; v < nv; ++v) {
        put(out, std::uint64_t{v + 1});
        out += '\n';
    }
    for (std::size_t v = 0; v < nv; ++v) {
        put_point(out, m, v);
        out += '\n';
    }
    out += "$EndNodes\n$Elements\n1 " + std::to_string(ne) + " 1 " + std::to_string(ne) + "\n" + std::to_string(m.dim) +
           " 1 " + std::to_string(type) + " " + std::to_string(ne) + "\n";
    for (std::size_t e = 0; e < ne; ++e) {
        put(out, std::uint64_t{e + 1});
        for (int i = 0; i < k; ++i) {
            out += ' ';
            put(out, std::uint64_t{m.conn[e * k + i] + 1ULL});
        }
        out += '\n';
    }
    return out + "$EndElements\n";
}

std::string vtu_text(const Mesh& m, const std::vector<CellField>& fields) {
    const std::size_t nv = m.vertices(), ne = m.elements();
    const int k = m.corners();
    std::string out =
        "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
        "<UnstructuredGrid>\n<Piece NumberOfPoints=\"" +
        std::to_string(nv) + "\" NumberOfCells=\"" + std::to_string(ne) + "\">\n";
    out += "<Points>\n<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n";
    for (std::size_t v = 0; v < nv; ++v) {
        put_point(out, m, v);
        out += '\n';
    }
    out += "</DataArray>\n</Points>\n<Cells>\n<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n";
    for (std::size_t e = 0; e < ne; ++e) {
        for (int i = 0; i < k; ++i) {
            put(out, std::uint64_t{m.conn[e * k + i]});
            out += i + 1 < k ? ' ' : '\n';
        }
    }
    out += "</DataArray>\n<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n";
    for (std::size_t e = 0; e < ne; ++e) {
        put(out, std::uint64_t{(e + 1) * k});
        out += '\n';
    }
    // VTK cell types: 5 triangle, 10 tetrahedron.
    out += "</DataArray>\n<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n";
    const std::string type = m.dim == 2 ? "5\n" : "10\n";
    for (std::size_t e = 0; e < ne; ++e) out += type;
    out += "</DataArray>\n</Cells>\n";
    if (!fields.empty()) {
        out += "<CellData>\n";
        for (const auto& f : fields) {
            if (f.values.size() != ne)
                throw std::invalid_argument("cell field " + f.name + " must have one value per element");
            out += "<DataArray type=\"Int64\" Name=\"" + f.name + "\" format=\"ascii\">\n";
            for (auto v : f.values) out += std::to_string(v) + '\n';
            out += "</DataArray>\n";
        }
        out += "</CellData>\n";
    }
    return out + "</Piece>\n</UnstructuredGrid>\n</VTKFile>\n";
}

}  // namespace suite::mesh
