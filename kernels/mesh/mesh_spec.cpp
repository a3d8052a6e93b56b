#include "kernels/mesh/mesh_spec.hpp"

#include <algorithm>
#include <array>
#include <map>
#include <mutex>

#include "harness/common/text.hpp"
#include "harness/common/units.hpp"
#include "kernels/mesh/edges.hpp"
#include "kernels/mesh/generate.hpp"
#include "kernels/mesh/readers.hpp"

namespace suite::mesh {

namespace {

const char* const accepted = "accepted: disk:refine=K, box:NX,NY,NZ[:refine=K], file:PATH[:refine=K]";

std::uint64_t parse_count(std::string_view text, std::string_view spec, const char* what, std::uint64_t min,
                          std::uint64_t max) {
    std::uint64_t v = 0;
    const bool digits = !text.empty() && text.size() <= 10 &&
                        std::all_of(text.begin(), text.end(), [](char c) { return c >= '0' && c <= '9'; });
    if (digits) v = std::stoull(std::string(text));
    if (!digits || v < min || v > max)
        throw UsageError("--mesh=" + std::string(spec) + ": " + what + " must be an integer from " +
                         std::to_string(min) + " to " + std::to_string(max) + ", found '" + std::string(text) + "'; " +
                         accepted);
    return v;
}

// Counts of the unrefined mesh of a spec: vertices, edges, faces (2D: = elements) and elements.
struct Base {
    int dim;
    std::uint64_t v, e, f, t;
};

Base count_mesh(const Mesh& m) {
    const EdgeTable edges = build_edges(m.view());
    Base b{m.dim, m.vertices(), edges.count(), m.elements(), m.elements()};
    if (m.dim == 3) {
        // Unique faces: every tetrahedron's 4 corner triples, sorted, counted once.
        std::vector<std::array<std::uint32_t, 3>> faces;
        faces.reserve(4 * m.elements());
        for (std::size_t e = 0; e < m.elements(); ++e)
            for (int skip = 0; skip < 4; ++skip) {
                std::array<std::uint32_t, 3> f{};
                for (int i = 0, n = 0; i < 4; ++i)
                    if (i != skip) f[n++] = m.conn[4 * e + i];
                std::sort(f.begin(), f.end());
                faces.push_back(f);
            }
        std::sort(faces.begin(), faces.end());
        b.f = static_cast<std::uint64_t>(std::unique(faces.begin(), faces.end()) - faces.begin());
    }
    return b;
}

// A file is read once per process to be counted; the counts are kept by path.
Base file_base(const std::string& path) {
    static std::mutex lock;
    static std::map<std::string, Base> cache;
    std::lock_guard<std::mutex> guard(lock);
    if (auto it = cache.find(path); it != cache.end()) return it->second;
    const Base b = count_mesh(read_mesh_file(path));
    cache.emplace(path, b);
    return b;
}

Base base_of(const MeshSpec& s) {
    switch (s.kind) {
        case MeshSpec::Kind::disk:
            return {2, 7, 12, 6, 6};
        case MeshSpec::Kind::box: {
            const std::uint64_t nx = s.nx, ny = s.ny, nz = s.nz;
            const std::uint64_t v = (nx + 1) * (ny + 1) * (nz + 1), t = 6 * nx * ny * nz;
            const std::uint64_t boundary = 4 * (nx * ny + ny * nz + nx * nz);  // each boundary square in 2 triangles
            const std::uint64_t f = (4 * t + boundary) / 2;
            return {3, v, v + f - t - 1, f, t};  // Euler: V - E + F - T = 1 for a ball
        }
        case MeshSpec::Kind::file:
            return file_base(s.path);
    }
    return {};
}

}  // namespace

MeshSpec parse_mesh_spec(std::string_view text) {
    MeshSpec s;
    s.text = std::string(text);
    std::string_view rest = text;
    // ":refine=K" ends any kind; a path may itself hold ':', so it is taken from the end.
    if (const auto at = rest.rfind(":refine="); at != std::string_view::npos) {
        s.refine = static_cast<int>(parse_count(rest.substr(at + 8), text, "refine", 0, 30));
        rest = rest.substr(0, at);
    }
    if (rest == "disk") {
        s.kind = MeshSpec::Kind::disk;
    } else if (rest.rfind("box:", 0) == 0) {
        s.kind = MeshSpec::Kind::box;
        const auto parts = split(rest.substr(4), ',');
        if (parts.size() != 3)
            throw UsageError("--mesh=" + s.text + ": box needs three cube counts NX,NY,NZ, e.g. box:64,64,64; " +
                             accepted);
        s.nx = static_cast<std::uint32_t>(parse_count(parts[0], text, "NX", 1, 4096));
        s.ny = static_cast<std::uint32_t>(parse_count(parts[1], text, "NY", 1, 4096));
        s.nz = static_cast<std::uint32_t>(parse_count(parts[2], text, "NZ", 1, 4096));
    } else if (rest.rfind("file:", 0) == 0) {
        s.kind = MeshSpec::Kind::file;
        s.path = std::string(rest.substr(5));
        if (s.path.empty())
            throw UsageError("--mesh=" + s.text + ": file: needs a path, e.g. file:../shared/meshes/unit_circle.txt; " +
                             accepted);
    } else {
        throw UsageError("unknown mesh '" + s.text + "'; " + accepted);
    }
    if (s.kind == MeshSpec::Kind::disk && text.find(":refine=") == std::string_view::npos)
        throw UsageError("--mesh=" + s.text + ": the disk needs its refinement level, e.g. disk:refine=6; " + accepted);
    return s;
}

MeshCounts mesh_counts(const MeshSpec& spec) {
    Base b = base_of(spec);
    for (int r = 0; r < spec.refine; ++r) {
        const std::uint64_t factor = b.dim == 2 ? 4 : 8;
        if (b.t > max_elements / factor)
            throw UsageError("--mesh=" + spec.text + " would have more than " + std::to_string(max_elements) +
                             " elements, the most the suite handles (32-bit positions); refine " + std::to_string(r) +
                             " times at most");
        Base n = b;
        n.v = b.v + b.e;
        if (b.dim == 2) {
            n.e = 2 * b.e + 3 * b.t;
            n.f = n.t = 4 * b.t;
        } else {
            n.e = 2 * b.e + 3 * b.f + b.t;  // each face gets 3 inner edges, each tetrahedron its diagonal
            n.f = 4 * b.f + 8 * b.t;
            n.t = 8 * b.t;
        }
        b = n;
    }
    if (b.t > max_elements)
        throw UsageError("--mesh=" + spec.text + " has " + std::to_string(b.t) + " elements, more than the " +
                         std::to_string(max_elements) + " the suite handles (32-bit positions)");
    return {b.dim, b.v, b.t};
}

Mesh load_mesh(const MeshSpec& spec) {
    mesh_counts(spec);  // the limits, before anything large is built
    if (spec.kind == MeshSpec::Kind::disk) return disk_mesh(spec.refine);
    Mesh m = spec.kind == MeshSpec::Kind::box ? box_mesh(spec.nx, spec.ny, spec.nz) : read_mesh_file(spec.path);
    for (int r = 0; r < spec.refine; ++r) m = refine_uniform(m);
    return m;
}

std::string disk_spec_for(std::uint64_t elements) {
    int k = 0;
    while (6ULL << (2 * k) < elements && k < 13) ++k;
    return "disk:refine=" + std::to_string(k);
}

}  // namespace suite::mesh
