#include "kernels/mpm/vtk.hpp"

#include <bit>
#include <charconv>
#include <cstdint>
#include <cstring>

namespace suite::mpm {

std::string base64(const void* data, std::size_t n) {
    static constexpr char alphabet[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    const auto* b = static_cast<const unsigned char*>(data);
    std::string out;
    out.reserve((n + 2) / 3 * 4);
    std::size_t i = 0;
    for (; i + 3 <= n; i += 3) {
        const std::uint32_t v = (std::uint32_t{b[i]} << 16) | (std::uint32_t{b[i + 1]} << 8) | b[i + 2];
        out += alphabet[v >> 18];
        out += alphabet[(v >> 12) & 63];
        out += alphabet[(v >> 6) & 63];
        out += alphabet[v & 63];
    }
    if (const std::size_t rest = n - i; rest > 0) {
        const std::uint32_t v = (std::uint32_t{b[i]} << 16) | (rest == 2 ? std::uint32_t{b[i + 1]} << 8 : 0u);
        out += alphabet[v >> 18];
        out += alphabet[(v >> 12) & 63];
        out += rest == 2 ? alphabet[(v >> 6) & 63] : '=';
        out += '=';
    }
    return out;
}

namespace {

constexpr const char* byte_order = std::endian::native == std::endian::little ? "LittleEndian" : "BigEndian";

// One inline binary DataArray: the UInt64 byte count and the values, base64 encoded together
// (VTK's "binary" format with header_type="UInt64", no compression).
template <class V>
void data_array(std::string& out, const char* type, const std::string& attributes, const V& values) {
    const std::uint64_t bytes = values.size() * sizeof(typename V::value_type);
    std::string raw(sizeof bytes + bytes, '\0');
    std::memcpy(raw.data(), &bytes, sizeof bytes);
    if (bytes) std::memcpy(raw.data() + sizeof bytes, values.data(), bytes);
    out += "<DataArray type=\"";
    out += type;
    out += "\" " + attributes + " format=\"binary\">\n" + base64(raw.data(), raw.size()) + "\n</DataArray>\n";
}

// The components of `columns` interleaved: c0[0] c1[0] ... c0[1] c1[1] ...
std::vector<double> interleave(const std::vector<const Array<double>*>& columns, std::size_t n) {
    std::vector<double> out(columns.size() * n);
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t k = 0; k < columns.size(); ++k) out[columns.size() * i + k] = (*columns[k])[i];
    return out;
}

std::string number(double v) {
    char buf[32];
    const auto [end, ec] = std::to_chars(buf, buf + sizeof buf, v);  // the shortest text that reads back the same
    return std::string(buf, end);
}

}  // namespace

std::string particles_vtu(const Particles& p) {
    const std::size_t n = p.size();
    std::string out = "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"";
    out += byte_order;
    out += "\" header_type=\"UInt64\">\n<UnstructuredGrid>\n<Piece NumberOfPoints=\"" + std::to_string(n) +
           "\" NumberOfCells=\"" + std::to_string(n) + "\">\n<Points>\n";
    data_array(out, "Float64", "Name=\"position\" NumberOfComponents=\"3\"", interleave({&p.x, &p.y, &p.z}, n));
    out += "</Points>\n<Cells>\n";
    std::vector<std::int64_t> connectivity(n), offsets(n);
    for (std::size_t i = 0; i < n; ++i) {
        connectivity[i] = static_cast<std::int64_t>(i);
        offsets[i] = static_cast<std::int64_t>(i + 1);
    }
    data_array(out, "Int64", "Name=\"connectivity\"", connectivity);
    data_array(out, "Int64", "Name=\"offsets\"", offsets);
    data_array(out, "UInt8", "Name=\"types\"", std::vector<std::uint8_t>(n, 1));  // 1: VTK_VERTEX
    out += "</Cells>\n<PointData Scalars=\"id\" Vectors=\"velocity\">\n";
    data_array(out, "UInt32", "Name=\"id\"", p.id);
    data_array(out, "Float64", "Name=\"velocity\" NumberOfComponents=\"3\"", interleave({&p.vx, &p.vy, &p.vz}, n));
    data_array(
        out, "Float64",
        "Name=\"stress\" NumberOfComponents=\"6\" ComponentName0=\"xx\" ComponentName1=\"yy\" ComponentName2=\"zz\" "
        "ComponentName3=\"xy\" ComponentName4=\"yz\" ComponentName5=\"zx\"",
        interleave({&p.stress[0], &p.stress[1], &p.stress[2], &p.stress[3], &p.stress[4], &p.stress[5]}, n));
    data_array(out, "Float64", "Name=\"volume\"", p.volume);
    data_array(out, "Float64", "Name=\"mass\"", p.mass);
    return out + "</PointData>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n";
}

std::string collection_pvd(const std::vector<SnapshotEntry>& snapshots) {
    std::string out = "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"";
    out += byte_order;
    out += "\">\n<Collection>\n";
    for (const auto& s : snapshots)
        out += "<DataSet timestep=\"" + number(s.time) + "\" group=\"\" part=\"0\" file=\"" + s.file + "\"/>\n";
    return out + "</Collection>\n</VTKFile>\n";
}

}  // namespace suite::mpm
