#include "kernels/fem/fem_point.hpp"

#include <omp.h>

#include <algorithm>
#include <cmath>

#include "harness/common/units.hpp"
#include "harness/kernel/blocks.hpp"
#include "kernels/fem/fem_mesh.hpp"
#include "kernels/mesh/mesh_spec.hpp"

namespace suite::fem {

std::string mesh_spec_of(const KernelConfig& cfg) {
    return cfg.mesh.empty() ? mesh::disk_spec_for(cfg.size) : cfg.mesh;
}

double param(const KernelConfig& cfg, const std::string& name) {
    const auto it = cfg.params.find(name);
    if (it == cfg.params.end())
        throw std::logic_error("finite element kernel: parameter '" + name + "' was not filled in");
    return cfg.param(name);
}

void FemPoint::setup(Arena& arena, const KernelConfig& cfg, Build build) {
    spec = mesh_spec_of(cfg);
    threads = cfg.threads;
    delta = cfg.params.count("delta") ? cfg.param("delta") : 0.0;
    const mesh::Mesh m = load_fem_mesh(spec, cfg.access.name, cfg.seed);
    const std::int64_t nv = static_cast<std::int64_t>(m.vertices()), ne = static_cast<std::int64_t>(m.elements());
    double* x = arena.allocate<double>("x", static_cast<std::size_t>(nv));
    double* y = arena.allocate<double>("y", static_cast<std::size_t>(nv));
    std::uint32_t* conn = arena.allocate<std::uint32_t>("conn", 3 * static_cast<std::size_t>(ne));
    scratch.v2e_ptr = arena.allocate<std::uint32_t>("vertex-elements-ptr", static_cast<std::size_t>(nv) + 1);
    scratch.v2e = arena.allocate<std::uint32_t>("vertex-elements", 3 * static_cast<std::size_t>(ne));
    scratch.fill = arena.allocate<std::uint32_t>("vertex-elements-fill", static_cast<std::size_t>(nv));
    scratch.partial = arena.allocate<std::uint64_t>("scan-sums", static_cast<std::size_t>(threads) + 1);
    pattern.n = nv;
    pattern.row_ptr = arena.allocate<std::uint32_t>("row-ptr", static_cast<std::size_t>(nv) + 1);
    pattern.col = nullptr;
    const PatternScratch s = scratch;
    const Pattern p = pattern;
    int team = 0;
#pragma omp parallel num_threads(threads) reduction(max : team)
    {
        team = omp_get_num_threads();
        const Block vb = my_block(nv), eb = my_block(ne);
        for (std::int64_t v = vb.lo; v < vb.hi; ++v) {
            x[v] = m.x[static_cast<std::size_t>(v)];
            y[v] = m.y[static_cast<std::size_t>(v)];
            s.v2e_ptr[v] = s.fill[v] = p.row_ptr[v] = 0;
        }
        for (std::int64_t e = eb.lo; e < eb.hi; ++e)
            for (int j = 0; j < 3; ++j)
                conn[3 * e + j] = m.conn[static_cast<std::size_t>(3 * e + j)], s.v2e[3 * e + j] = 0;
#pragma omp single
        s.v2e_ptr[nv] = p.row_ptr[nv] = 0;
    }
    require_team_size(team, threads);
    mesh = {nv, ne, x, y, conn};
    build_pattern(mesh, pattern, scratch);
    const std::uint64_t nz = pattern.nnz();
    pattern.col = arena.allocate<std::uint32_t>("col", nz);
    const bool with_values = build == Build::matrices;
    matrices.pattern = pattern;
    if (with_values) {
        matrices.a = arena.allocate<double>("A", nz);
        matrices.m = arena.allocate<double>("M", nz);
    }
    const Pattern q = pattern;
    const Matrices mats = matrices;
#pragma omp parallel
    {
        const Block rb = my_block(nv);
        for (std::uint32_t k = q.row_ptr[rb.lo]; k < q.row_ptr[rb.hi]; ++k) {
            q.col[k] = 0;
            if (with_values) mats.a[k] = mats.m[k] = 0;
        }
    }
    build_pattern(mesh, pattern, scratch);
    matrices.pattern = pattern;
    if (with_values) assemble(mesh, matrices, delta, plan_strategy(mesh, Strategy::serial, threads));
}

std::string FemPoint::describe(const KernelConfig& cfg) const {
    return "mesh " + spec + " (" + std::to_string(mesh.ne) + " triangles, " + std::to_string(mesh.nv) + " vertices, " +
           std::to_string(nnz()) + " nonzeros), " + cfg.access.name + ": ";
}

double* FemPoint::vector(Arena& arena, const std::string& name) const {
    double* v = arena.allocate<double>(name, static_cast<std::size_t>(mesh.nv));
    const std::int64_t n = mesh.nv;
#pragma omp parallel
    {
        const Block rb = my_block(n);
        std::fill(v + rb.lo, v + rb.hi, 0.0);
    }
    return v;
}

void validate_fem(const KernelConfig& cfg, const std::string& kernel, bool takes_delta) {
    if (takes_delta) {
        const double d = param(cfg, "delta");
        if (!std::isfinite(d) || d < 0)
            throw UsageError("--delta=" + format_number(d) + " for " + kernel +
                             ": δ must be a finite number >= 0 (default 0.05)");
    }
    const std::string spec = mesh_spec_of(cfg);
    // The kernel's arrays, the mesh while it is loaded and ordered (three copies at most), and
    // verify()'s serial reference assembly; nonzeros <= 2 nv + 3 ne for triangles. Estimated
    // from the spec (a file's counts come from reading it), before the mesh is built to be checked.
    const mesh::MeshCounts c = mesh::mesh_counts(mesh::parse_mesh_spec(spec));
    const std::uint64_t nv = c.vertices, ne = c.elements, nz = 2 * nv + 3 * ne;
    const std::uint64_t need = nv * (16 + 16 + 8 * 8) + ne * 24 + nz * 20 + 3 * (ne * 12 + nv * 16) + nz * 20 + ne * 24;
    const std::uint64_t have = available_memory_bytes(MemoryPolicy{});
    if (need > have)
        throw UsageError(kernel + " on --mesh=" + spec + " (" + std::to_string(ne) + " triangles) needs about " +
                         format_bytes(need) + ", more than the " + format_bytes(have) +
                         " of memory available; use a smaller mesh");
    check_fem_spec(spec);
}

ParamInfo delta_param() {
    return {"delta", 0.05, "δ of the waveguide, k² = (100 + δ) exp(-50 (x² + y²)) - 100; finite, >= 0 (fem kernels)"};
}

std::vector<ParamInfo> solver_params(bool cg, bool eigen) {
    std::vector<ParamInfo> out;
    if (cg) {
        out.push_back({"cg-tol", 1e-10,
                       "CG stops when ||r|| <= cg-tol ||f||; in (0, 1) (fem-cg, fem-eigen and their -dist twins)"});
        out.push_back(
            {"cg-max", 100000,
             "most CG iterations of one solve, a whole number >= 1 (fem-cg, fem-eigen and their -dist twins)"});
    }
    if (eigen)
        out.push_back(
            {"tol", 1e-8,
             "the inverse iteration stops when |λ - λ_old| <= tol |λ_old|; in (0, 1) (fem-eigen, fem-eigen-dist)"});
    return out;
}

void validate_solver_params(const KernelConfig& cfg, const std::string& name, bool cg, bool eigen) {
    if (cg) {
        const double t = param(cfg, "cg-tol"), m = param(cfg, "cg-max");
        if (!(t > 0 && t < 1))
            throw UsageError("--cg-tol=" + format_number(t) + " for " + name +
                             ": the tolerance must lie strictly between 0 and 1");
        if (!(m >= 1 && m <= 2e9 && m == std::floor(m)))
            throw UsageError("--cg-max=" + format_number(m) + " for " + name +
                             ": accepted: a whole number from 1 to 2000000000");
    }
    if (eigen) {
        const double t = param(cfg, "tol");
        if (!(t > 0 && t < 1))
            throw UsageError("--tol=" + format_number(t) + " for " + name +
                             ": the tolerance must lie strictly between 0 and 1");
    }
}

void set_mesh_sizing(KernelEntry& e) {
    e.info.axis = AccessAxis::ordering;
    e.info.accesses = fem_orderings().names();
    e.info.size_kind = SizeKind::count;
    e.mesh_elements = [](const std::string& spec) { return mesh::mesh_counts(mesh::parse_mesh_spec(spec)).elements; };
    e.default_meshes = {"disk:refine=7"};
    e.test_size = 1536;  // disk:refine=4
}

}  // namespace suite::fem
