// `suite matrix`: the P1 Helmholtz matrix A of a mesh under vertex orderings, as the thesis's
// section 5.5 compared them: per ordering the bandwidth and profile, the time to compute the
// ordering, CHOLMOD's Cholesky factor of A (its nonzeros, flops, factorisation and solve time)
// and the time of the suite's own SpMV on the permuted matrix. The SFC orderings and RCM come
// from the mesh toolkit (kernels/sfc), AMD from SuiteSparse, nested dissection from METIS; every
// ordering is applied to the same assembled A as a symmetric permutation P A Pᵀ.
// Into --out=DIR: matrix.json, matrix.md (a table to paste into a report), spy-ORDERING.png and
// spy.png (plots/matrix.py), and with --export=mtx ORDERING.mtx (Matrix Market).
#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "harness/cli/commands.hpp"
#include "harness/cli/parse.hpp"
#include "harness/cli/plotter.hpp"
#include "harness/common/output_file.hpp"
#include "harness/common/stats.hpp"
#include "harness/common/units.hpp"
#include "harness/kernel/blocks.hpp"
#include "kernels/fem/assembly.hpp"
#include "kernels/fem/csr.hpp"
#include "kernels/fem/fem_mesh.hpp"
#include "kernels/fem/matrix_study.hpp"
#include "kernels/fem/sparse_libs.hpp"
#include "kernels/mesh/mesh_spec.hpp"

namespace suite {

using namespace fem;

namespace {

const char* const footer = R"(
The matrix is A of the finite element kernels (P1 triangles, -Δu - k²u with a Neumann boundary,
k² = (100 + δ) exp(-50 (x² + y²)) - 100), assembled once in the mesh's own order. An ordering
numbers the vertices anew and A becomes P A Pᵀ. A is positive definite while the waveguide's
lowest eigenvalue is positive (88.3 at δ = 0.05), so CHOLMOD factorises A itself, in the given
order (no ordering or postordering of its own); a factor over --max-factor is analysed, not
computed. Times: the ordering's computation (mesh toolkit: keys, sort and renumbering of the
mesh; AMD and METIS: the library call on A's graph), then the median of --reps factorisations,
solves of A x = A·1 (x must come back as 1) and SpMVs with the suite's fem-spmv loop (checked
against the unpermuted product).

Examples:
  ./suite matrix --mesh=disk:refine=5 --out=matrix
  ./suite matrix --mesh=file:../shared/meshes/unit_circle_fine.txt:refine=2 --out=thesis-r2
  ./suite matrix --mesh=disk:refine=4 --ordering=morton,rcm,amd,nd --export=mtx --out=m

In DIR: matrix.json (everything, with a spy grid per ordering), matrix.md (the table),
spy-ORDERING.png and spy.png (all side by side), ORDERING.mtx with --export=mtx.
)";

const std::vector<std::string> accepted = {"natural", "random", "morton", "hilbert", "rcm", "amd", "nd"};
constexpr int spy_bins = 256;

struct Options {
    std::string mesh = "disk:refine=5";
    std::string orderings = "natural,random,morton,hilbert,rcm,amd,nd";
    std::string out;
    std::string exports;
    std::string delta = "0.05";
    std::string max_factor = "2GiB";
    int reps = 5;
    int threads = 1;
    std::uint64_t seed = 1;
    bool no_png = false;
    bool dry_run = false;
};

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

std::string join(const std::vector<std::string>& v, const char* sep = ", ") {
    std::string s;
    for (const auto& x : v) s += (s.empty() ? "" : sep) + x;
    return s;
}

std::string source_of(const std::string& name) {
    if (name == "amd") return "SuiteSparse AMD";
    if (name == "nd") return "METIS_NodeND";
    return "mesh toolkit (kernels/sfc)";
}

// y = B x with the suite's SpMV loop, `threads` threads in static row blocks.
void spmv(const Csr& b, const double* x, double* y, int threads) {
    const Pattern p{b.n, const_cast<std::uint32_t*>(b.row_ptr.data()), const_cast<std::uint32_t*>(b.col.data())};
#pragma omp parallel num_threads(threads)
    {
        const Block blk = my_block(b.n);
        spmv_rows(p, b.val.data(), x, y, blk.lo, blk.hi);
    }
}

struct Row {
    std::string name;
    double order_s = 0;
    Structure st;
    double lnz = 0, flops = 0, factor_s = NAN, solve_s = NAN, spmv_s = 0;
    bool factorised = false;
};

std::string fmt(const char* f, double v) {
    char b[64];
    std::snprintf(b, sizeof b, f, v);
    return b;
}

}  // namespace

int cmd_matrix(const std::vector<std::string>& args) {
    CLI::App app{"suite matrix: the finite element matrix's structure, Cholesky fill and SpMV time under vertex orderings"};
    app.footer(footer);
    app.get_formatter()->column_width(28);
    Options o;
    app.add_option("--mesh", o.mesh, "a triangle mesh: disk:refine=K | file:PATH[:refine=K] (default disk:refine=5)");
    app.add_option("--ordering", o.orderings, "natural, random, morton, hilbert, rcm, amd, nd (default: all)");
    app.add_option("--out,-o", o.out, "directory for matrix.json, matrix.md, the spy plots and exports (created if missing)");
    app.add_option("--export", o.exports, "mtx: also write each permuted A as ORDERING.mtx (Matrix Market; needs --out)");
    app.add_option("--delta", o.delta, "δ of the waveguide; finite, >= 0 (default 0.05)");
    app.add_option("--max-factor", o.max_factor, "largest Cholesky factor computed, in bytes of L's values and row indices (default 2GiB)");
    add_whole_option(app, "--reps", o.reps, 1, 1000, "factorisations, solves and SpMVs timed per ordering, 1 to 1000 (default 5)");
    add_whole_option(app, "--threads,-t", o.threads, 1, 1024, "threads of the SpMV (default 1; CHOLMOD uses its own)");
    add_seed_option(app, o.seed, "seed of the random ordering, 0 to 18446744073709551615 (default 1)");
    app.add_flag("--no-png", o.no_png, "write the numbers only");
    app.add_flag("--dry-run", o.dry_run, "check the options (and read the mesh file), say what would be written, and stop");
    if (!parse_command_line(app, "suite matrix", args)) return 0;

    // Everything is checked before anything is computed or written.
    const std::vector<std::string> orderings = parse_name_list(o.orderings, "--ordering");
    require_known(orderings, accepted, "ordering");
    const double delta = parse_finite(o.delta, "--delta");
    if (delta < 0) throw UsageError("--delta=" + o.delta + ": δ must be >= 0 (the waveguide's k² = (100 + δ) exp(-50 r²) - 100)");
    double max_factor = 0;
    try {
        max_factor = static_cast<double>(parse_bytes(o.max_factor));
    } catch (const UsageError& e) {
        throw UsageError("--max-factor=" + o.max_factor + ": " + e.what());
    }
    if (!o.exports.empty() && o.exports != "mtx") throw UsageError("--export=" + o.exports + ": the one export format is mtx (Matrix Market)");
    if (!o.exports.empty() && o.out.empty()) throw UsageError("--export=mtx writes into the --out directory: give --out=DIR");
    if (const std::string missing = sparse_libs_missing(); !missing.empty())
        throw UsageError("suite matrix needs " + missing + ", which this build did not find; install (scripts/install-deps.sh does) and rebuild");
    const mesh::MeshSpec spec = mesh::parse_mesh_spec(o.mesh);
    check_fem_spec(o.mesh);  // triangles, no isolated vertices, no inverted triangles
    const std::vector<FileIdentity> inputs = identify_inputs({spec.kind == mesh::MeshSpec::Kind::file ? spec.path : ""});
    if (o.dry_run) {
        if (!o.out.empty()) OutputDir::check(o.out, "--out");
        std::printf("mesh %s; orderings %s%s\n", o.mesh.c_str(), join(orderings).c_str(),
                    o.out.empty() ? "; the table on the console only" : ("; into " + o.out + ": matrix.json, matrix.md" + (o.no_png ? "" : ", spy plots") +
                                                                         (o.exports.empty() ? "" : ", ORDERING.mtx")).c_str());
        return 0;
    }

    const mesh::Mesh m = load_fem_mesh(o.mesh, "natural", o.seed);
    const MeshArrays arrays{static_cast<std::int64_t>(m.vertices()), static_cast<std::int64_t>(m.elements()), m.x.data(), m.y.data(), m.conn.data()};
    AssembledCsr assembled = assemble_reference(arrays, delta);
    Csr a;
    a.n = arrays.nv;
    a.row_ptr = std::move(assembled.row_ptr);
    a.col = std::move(assembled.col);
    a.val = std::move(assembled.a);
    const double asymmetry = symmetrize_from_lower(a);
    if (!(asymmetry <= 1e-12)) throw std::runtime_error("the assembled A is not symmetric: entries differ from their twins by " + fmt("%.3g", asymmetry));
    try {
        check_definite(a);
    } catch (const NotDefinite& e) {
        (void)e;
        throw UsageError("--mesh=" + o.mesh + " --delta=" + o.delta +
                         ": A is not positive definite (CHOLMOD met a non-positive pivot), so it has no Cholesky factor; δ deepens the well, "
                         "and at this one the lowest eigenvalue is negative: give a smaller δ (the default 0.05 gives 88.3)");
    }
    const OutputDir out = o.out.empty() ? OutputDir() : OutputDir::claim(o.out, "--out", inputs);

    std::printf("mesh %s: %zu triangles, %lld rows, %llu nonzeros; A at δ = %g; SpMV on %d thread(s), medians of %d\n\n", o.mesh.c_str(), m.elements(),
                static_cast<long long>(a.n), static_cast<unsigned long long>(a.nnz()), delta, o.threads, o.reps);
    std::printf("%-8s %10s %10s %14s %13s %11s %11s %11s %11s\n", "ordering", "order ms", "bandwidth", "profile", "nnz(L)", "GFlop", "factor ms",
                "solve ms", "SpMV ms");
    nlohmann::json doc = {{"mesh", o.mesh},
                          {"triangles", m.elements()},
                          {"rows", a.n},
                          {"nonzeros", a.nnz()},
                          {"delta", delta},
                          {"matrix", "A = K - k² M (the fem kernels' stiffness matrix), symmetric positive definite here; each upper entry set to its lower twin, from which assembly's summation order made it differ by round-off"},
                          {"asymmetry_removed", asymmetry},
                          {"threads_spmv", o.threads},
                          {"reps", o.reps},
                          {"seed", o.seed},
                          {"libraries", nlohmann::json::object()},
                          {"orderings", nlohmann::json::array()}};
    for (const auto& [lib, version] : sparse_lib_versions()) doc["libraries"][lib] = version;

    std::vector<double> x(static_cast<std::size_t>(a.n)), y_ref(static_cast<std::size_t>(a.n)), xb(x.size()), yb(x.size());
    for (std::int64_t i = 0; i < a.n; ++i) x[static_cast<std::size_t>(i)] = 1.0 + 0.5 * std::sin(0.37 * static_cast<double>(i));
    spmv(a, x.data(), y_ref.data(), 1);
    std::vector<Row> rows;
    for (const auto& name : orderings) {
        Row r;
        r.name = name;
        const auto t0 = Clock::now();
        std::vector<std::uint32_t> perm = name == "amd" ? amd_order(a) : name == "nd" ? nested_dissection_order(a) : mesh_vertex_order(m, name, o.seed);
        r.order_s = since(t0);
        if (!is_permutation(perm, static_cast<std::size_t>(a.n))) throw std::runtime_error(name + ": the ordering is not a permutation of the rows");
        const Csr b = permute_symmetric(a, perm);
        r.st = structure(b);
        nlohmann::json entry = {{"ordering", name}, {"source", source_of(name)}, {"ordering_seconds", r.order_s},
                                {"bandwidth", r.st.bandwidth}, {"profile", r.st.profile}};

        // The factor: analysed first; computed when it fits under --max-factor.
        const Symbolic sym = analyse(b);
        r.lnz = sym.factor_nnz;
        r.flops = sym.flops;
        const double factor_bytes = 12.0 * sym.factor_nnz;  // a value and a row index a nonzero
        nlohmann::json fj = {{"factor_nonzeros", sym.factor_nnz}, {"flops", sym.flops}, {"analyse_seconds", sym.seconds}, {"factor_bytes", factor_bytes}};
        if (factor_bytes > max_factor) {
            fj["computed"] = false;
            fj["reason"] = "the factor would take " + format_bytes(static_cast<std::uint64_t>(factor_bytes)) + ", above --max-factor=" + o.max_factor;
        } else {
            const Factorisation f = factorise(b, o.reps);
            const bool ok = f.residual < 1e-8 && f.max_error < 1e-6;
            if (!ok)
                throw std::runtime_error(name + ": the Cholesky solve did not reproduce x = 1 (residual " + fmt("%.3g", f.residual) + ", max error " +
                                         fmt("%.3g", f.max_error) + ")");
            r.factorised = true;
            r.factor_s = summarise(f.factor_seconds).median;
            r.solve_s = summarise(f.solve_seconds).median;
            fj["computed"] = true;
            fj["method"] = "CHOLMOD " + f.method;
            fj["factor_seconds"] = {{"median", r.factor_s}, {"min", *std::min_element(f.factor_seconds.begin(), f.factor_seconds.end())}, {"samples", f.factor_seconds}};
            fj["solve_seconds"] = {{"median", r.solve_s}, {"min", *std::min_element(f.solve_seconds.begin(), f.solve_seconds.end())}, {"samples", f.solve_seconds}};
            fj["verification"] = {{"residual", f.residual}, {"max_error", f.max_error}, {"passed", true},
                                  {"detail", "A x = A·1 solved with the factor: x within 1e-6 of 1, ||b - A x|| / ||b|| < 1e-8"}};
        }
        entry["cholesky"] = fj;

        // SpMV on the permuted matrix: x permuted alike, so y must be y_ref permuted.
        for (std::int64_t i = 0; i < a.n; ++i) xb[static_cast<std::size_t>(i)] = x[perm[static_cast<std::size_t>(i)]];
        std::vector<double> times;
        spmv(b, xb.data(), yb.data(), o.threads);  // warm-up
        for (int k = 0; k < o.reps; ++k) {
            const auto s0 = Clock::now();
            spmv(b, xb.data(), yb.data(), o.threads);
            times.push_back(since(s0));
        }
        double worst = 0;
        for (std::int64_t i = 0; i < a.n; ++i) {
            double scale = 0;
            for (std::uint32_t k = a.row_ptr[perm[i]]; k < a.row_ptr[perm[i] + 1]; ++k) scale += std::fabs(a.val[k] * x[a.col[k]]);
            worst = std::max(worst, std::fabs(yb[static_cast<std::size_t>(i)] - y_ref[perm[i]]) / (scale > 0 ? scale : 1));
        }
        if (!(worst <= 1e-12)) throw std::runtime_error(name + ": the SpMV of the permuted matrix differs from the unpermuted one by " + fmt("%.3g", worst));
        r.spmv_s = summarise(times).median;
        const double bytes = 12.0 * static_cast<double>(a.nnz()) + 4.0 * static_cast<double>(a.n + 1) + 16.0 * static_cast<double>(a.n);
        entry["spmv"] = {{"threads", o.threads}, {"seconds", {{"median", r.spmv_s}, {"min", *std::min_element(times.begin(), times.end())}, {"samples", times}}},
                         {"gbps_median", bytes / r.spmv_s / 1e9},
                         {"verification", {{"max_error", worst}, {"passed", true}, {"detail", "y = (P A Pᵀ)(P x) equals P (A x) to 1e-12 of each row's Σ|a x|"}}}};
        int bins = 0;
        const std::vector<std::uint64_t> grid = spy_grid(b, spy_bins, &bins);
        entry["spy"] = {{"bins", bins}, {"counts", grid}};
        if (!o.exports.empty()) {
            const std::string file = name + ".mtx";
            out.write(file, matrix_market(b, {"suite matrix: A of " + o.mesh + " at delta " + o.delta + ", vertices in " + name + " order"}));
            entry["export"] = file;
        }
        doc["orderings"].push_back(entry);
        std::printf("%-8s %10.1f %10llu %14llu %13.0f %11.3f %11s %11s %11.3f\n", name.c_str(), 1e3 * r.order_s, static_cast<unsigned long long>(r.st.bandwidth),
                    static_cast<unsigned long long>(r.st.profile), r.lnz, r.flops / 1e9, r.factorised ? fmt("%.1f", 1e3 * r.factor_s).c_str() : "-",
                    r.factorised ? fmt("%.2f", 1e3 * r.solve_s).c_str() : "-", 1e3 * r.spmv_s);
        std::fflush(stdout);
        rows.push_back(r);
    }
    for (const auto& r : rows)
        if (!r.factorised) std::printf("%s: factor analysed, not computed (over --max-factor=%s)\n", r.name.c_str(), o.max_factor.c_str());
    if (o.out.empty()) return 0;

    std::string md = "Matrix A of `" + o.mesh + "` (" + std::to_string(a.n) + " rows, " + std::to_string(a.nnz()) + " nonzeros, δ = " + o.delta +
                     "); Cholesky by CHOLMOD in the given order; SpMV on " + std::to_string(o.threads) + " thread(s); times are medians of " +
                     std::to_string(o.reps) + ".\n\n| ordering | ordering ms | bandwidth | profile | nnz(L) | fill nnz(L)/nnz(A) | GFlop | factor ms | solve ms | SpMV ms |\n"
                     "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
    for (const auto& r : rows)
        md += "| " + r.name + " | " + fmt("%.1f", 1e3 * r.order_s) + " | " + std::to_string(r.st.bandwidth) + " | " + std::to_string(r.st.profile) + " | " +
              fmt("%.0f", r.lnz) + " | " + fmt("%.2f", r.lnz / static_cast<double>(a.nnz())) + " | " + fmt("%.3f", r.flops / 1e9) + " | " +
              (r.factorised ? fmt("%.1f", 1e3 * r.factor_s) : "not computed") + " | " + (r.factorised ? fmt("%.2f", 1e3 * r.solve_s) : "-") + " | " +
              fmt("%.3f", 1e3 * r.spmv_s) + " |\n";
    out.write("matrix.md", md);
    out.write("matrix.json", doc.dump(1) + "\n");
    std::string pngs = "";
    if (!o.no_png) {
        const Plotter p = find_plotter("matrix.py");
        const std::string why = p.reason.empty() ? draw(p, o.out) : p.reason;
        if (why.empty()) pngs = ", spy-ORDERING.png, spy.png";
        else std::cerr << "suite: note: no spy plots: " << why << "\n";
    }
    std::printf("\nwrote %s (matrix.json, matrix.md%s%s)\n", o.out.c_str(), pngs.c_str(), o.exports.empty() ? "" : ", ORDERING.mtx");
    return 0;
}

}  // namespace suite
