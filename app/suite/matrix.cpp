// `suite matrix`: the P1 Helmholtz matrix A of a mesh under vertex orderings, as the thesis's
// section 5.5 compared them: per ordering the bandwidth and profile, the time to compute the
// ordering, CHOLMOD's Cholesky factor of A (its nonzeros, flops, factorisation and solve time)
// and the time of the suite's own SpMV on the permuted matrix. The study itself is
// kernels/fem/ordering_study; this file checks the options and renders. The SFC orderings and
// RCM come from the mesh toolkit (kernels/sfc), AMD from SuiteSparse, nested dissection from
// METIS; every ordering is applied to the same assembled A as a symmetric permutation P A Pᵀ.
// The files are rewritten after every ordering ("complete": false until the last), so that an
// interrupted study keeps the orderings it finished.
// Into --out=DIR: matrix.json, matrix.md (a table to paste into a report), spy-ORDERING.png and
// spy.png (plots/matrix.py), and with --export=mtx ORDERING.mtx (Matrix Market).
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "app/suite/commands.hpp"
#include "app/suite/frame.hpp"
#include "app/suite/parse.hpp"
#include "app/suite/plotter.hpp"
#include "harness/common/output_file.hpp"
#include "harness/common/text.hpp"
#include "harness/common/units.hpp"
#include "harness/kernel/arena.hpp"
#include "kernels/fem/fem_mesh.hpp"
#include "kernels/fem/ordering_study.hpp"
#include "kernels/mesh/mesh_spec.hpp"
#include "kernels/sfc/orderings.hpp"

namespace suite {
namespace matrix_command {
namespace {

using namespace fem;

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

constexpr int spy_bins = 256;

struct Options {
    std::string mesh = "disk:refine=5";
    std::string orderings = join(matrix_orderings().names(), ",");
    std::string out;
    std::string exports;
    std::string delta = "0.05";
    std::string max_factor = "2GiB";
    int reps = 5;
    int threads = 1;
    std::uint64_t seed = 1;
    bool no_png = false;
    bool dry_run = false;
    bool replace = false;
};

std::string fmt(const char* f, double v) {
    char b[64];
    std::snprintf(b, sizeof b, f, v);
    return b;
}

std::string markdown(const Options& o, const Csr& a, const std::vector<OrderingStudy>& rows) {
    std::string md = "Matrix A of `" + o.mesh + "` (" + std::to_string(a.n) + " rows, " + std::to_string(a.nnz()) +
                     " nonzeros, δ = " + o.delta + "); Cholesky by CHOLMOD in the given order; SpMV on " +
                     std::to_string(o.threads) + " thread(s); times are medians of " + std::to_string(o.reps) +
                     ".\n\n| ordering | ordering ms | bandwidth | profile | nnz(L) | fill nnz(L)/nnz(A) | GFlop | "
                     "factor ms | solve ms | SpMV ms |\n"
                     "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
    for (const auto& r : rows)
        md += "| " + r.name + " | " + fmt("%.1f", 1e3 * r.order_s) + " | " + std::to_string(r.structure.bandwidth) +
              " | " + std::to_string(r.structure.profile) + " | " + fmt("%.0f", r.symbolic.factor_nnz) + " | " +
              fmt("%.2f", r.symbolic.factor_nnz / static_cast<double>(a.nnz())) + " | " +
              fmt("%.3f", r.symbolic.flops / 1e9) + " | " +
              (r.factorised ? fmt("%.1f", 1e3 * r.factor_median_s) : "not computed") + " | " +
              (r.factorised ? fmt("%.2f", 1e3 * r.solve_median_s) : "-") + " | " + fmt("%.3f", 1e3 * r.spmv_median_s) +
              " |\n";
    return md;
}

nlohmann::json seconds_json(const std::vector<double>& samples, double median) {
    return {{"median", median}, {"min", *std::min_element(samples.begin(), samples.end())}, {"samples", samples}};
}

nlohmann::json ordering_json(const OrderingStudy& r, const Options& o) {
    nlohmann::json entry = {{"ordering", r.name},
                            {"source", r.source},
                            {"ordering_seconds", r.order_s},
                            {"bandwidth", r.structure.bandwidth},
                            {"profile", r.structure.profile}};
    nlohmann::json fj = {{"factor_nonzeros", r.symbolic.factor_nnz},
                         {"flops", r.symbolic.flops},
                         {"analyse_seconds", r.symbolic.seconds},
                         {"factor_bytes", r.factor_bytes}};
    if (!r.factorised) {
        fj["computed"] = false;
        fj["reason"] = "the factor would take " + format_bytes(static_cast<std::uint64_t>(r.factor_bytes)) +
                       (r.factor_over_memory
                            ? ", and twice that is more than the " +
                                  format_bytes(static_cast<std::uint64_t>(r.memory_available)) + " of memory available"
                            : ", above --max-factor=" + o.max_factor);
    } else {
        fj["computed"] = true;
        fj["method"] = "CHOLMOD " + r.factor.method;
        fj["factor_seconds"] = seconds_json(r.factor.factor_seconds, r.factor_median_s);
        fj["solve_seconds"] = seconds_json(r.factor.solve_seconds, r.solve_median_s);
        fj["verification"] = {
            {"residual", r.factor.residual},
            {"max_error", r.factor.max_error},
            {"passed", true},
            {"detail", "A x = A·1 solved with the factor: x within 1e-6 of 1, ||b - A x|| / ||b|| < 1e-8"}};
    }
    entry["cholesky"] = fj;
    entry["spmv"] = {{"threads", o.threads},
                     {"seconds", seconds_json(r.spmv_seconds, r.spmv_median_s)},
                     {"gbps_median", r.spmv_bytes / r.spmv_median_s / 1e9},
                     {"verification",
                      {{"max_error", r.spmv_max_error},
                       {"passed", true},
                       {"detail", "y = (P A Pᵀ)(P x) equals P (A x) to 1e-12 of each row's Σ|a x|"}}}};
    entry["spy"] = {{"bins", r.spy_bins}, {"counts", r.spy}};
    return entry;
}

}  // namespace
}  // namespace matrix_command

int cmd_matrix(const std::vector<std::string>& args) {
    using namespace matrix_command;
    CLI::App app{
        "suite matrix: the finite element matrix's structure, Cholesky fill and SpMV time under vertex orderings"};
    app.footer("Orderings:\n" + matrix_orderings().listed() + footer);
    app.get_formatter()->column_width(28);
    Options o;
    app.add_option("--mesh", o.mesh, "a triangle mesh: disk:refine=K | file:PATH[:refine=K] (default disk:refine=5)");
    app.add_option("--ordering", o.orderings,
                   "one or more of " + matrix_orderings().accepted() + " (default: all; below)");
    app.add_option("--out,-o", o.out,
                   "directory for matrix.json, matrix.md, the spy plots and exports (created if missing)");
    app.add_option("--export", o.exports,
                   "mtx: also write each permuted A as ORDERING.mtx (Matrix Market; needs --out)");
    app.add_option("--delta", o.delta, "δ of the waveguide; finite, >= 0 (default 0.05)");
    app.add_option("--max-factor", o.max_factor,
                   "largest Cholesky factor computed, in bytes of L's values and row indices (default 2GiB)");
    add_whole_option(app, "--reps", o.reps, 1, 1000,
                     "factorisations, solves and SpMVs timed per ordering, 1 to 1000 (default 5)");
    add_whole_option(app, "--threads,-t", o.threads, 1, 1024, "threads of the SpMV (default 1; CHOLMOD uses its own)");
    add_seed_option(app, o.seed, "seed of the random ordering, 0 to 18446744073709551615 (default 1)");
    app.add_flag("--no-png", o.no_png, "write the numbers only");
    app.add_flag("--replace", o.replace, "replace the files of an earlier run in --out (refused without it)");
    app.add_flag("--dry-run", o.dry_run,
                 "check the options (and read the mesh file), say what would be written, and stop");
    if (!parse_command_line(app, "suite matrix", args)) return 0;

    // Everything is checked before anything is computed or written.
    const std::vector<std::string> orderings = parse_name_list(o.orderings, "--ordering");
    for (const auto& name : orderings) matrix_orderings().at(name);
    const double delta = parse_finite(o.delta, "--delta");
    if (delta < 0)
        throw UsageError("--delta=" + o.delta + ": δ must be >= 0 (the waveguide's k² = (100 + δ) exp(-50 r²) - 100)");
    double max_factor = 0;
    try {
        max_factor = static_cast<double>(parse_bytes(o.max_factor));
    } catch (const UsageError& e) {
        throw UsageError("--max-factor=" + o.max_factor + ": " + e.what());
    }
    if (o.threads > omp_get_thread_limit())
        throw UsageError("--threads=" + std::to_string(o.threads) + ": OpenMP allows at most " +
                         std::to_string(omp_get_thread_limit()) + " (OMP_THREAD_LIMIT); ask for fewer or unset it");
    if (!o.exports.empty() && o.exports != "mtx")
        throw UsageError("--export=" + o.exports + ": the one export format is mtx (Matrix Market)");
    if (!o.exports.empty() && o.out.empty())
        throw UsageError("--export=mtx writes into the --out directory: give --out=DIR");
    if (const std::string missing = sparse_libs_missing(); !missing.empty())
        throw UsageError("suite matrix needs " + missing +
                         ", which this build did not find; install (scripts/install-deps.sh does) and rebuild");
    if (!o.no_png && !o.out.empty()) require_plotter("matrix.py", "--no-png");
    const mesh::MeshSpec spec = mesh::parse_mesh_spec(o.mesh);
    const std::vector<FileIdentity> inputs =
        identify_inputs({spec.kind == mesh::MeshSpec::Kind::file ? spec.path : ""});
    if (!o.out.empty())
        OutputDir::check(
            o.out,
            DirPolicy{.option = "--out", .command = "suite matrix", .inputs = inputs, .replace_earlier = o.replace});
    // The memory, from the mesh's counts, before the mesh is built.
    const mesh::MeshCounts counts = mesh::mesh_counts(spec);
    const std::uint64_t need = study_bytes(counts), have = available_memory_bytes(MemoryPolicy{});
    if (need > have)
        throw UsageError("--mesh=" + o.mesh + " (" + std::to_string(counts.elements) + " triangles) needs about " +
                         format_bytes(need) + " for the study, more than the " + format_bytes(have) +
                         " of memory available; use a smaller mesh");
    if (o.dry_run) {
        check_fem_spec(o.mesh);  // triangles, no isolated vertices, no inverted triangles (the run's load_fem_mesh
                                 // checks the same)
        std::printf(
            "mesh %s: %llu triangles, about %s of memory (%s available) besides each ordering's factor; orderings "
            "%s%s\n",
            o.mesh.c_str(), static_cast<unsigned long long>(counts.elements), format_bytes(need).c_str(),
            format_bytes(have).c_str(), join(orderings, ", ").c_str(),
            o.out.empty() ? "; the table on the console only"
                          : ("; into " + o.out + ": matrix.json, matrix.md" + (o.no_png ? "" : ", spy plots") +
                             (o.exports.empty() ? "" : ", ORDERING.mtx"))
                                .c_str());
        return 0;
    }

    const mesh::Mesh m = load_fem_mesh(o.mesh, sfc::as_given_name(), o.seed);
    MatrixUnderStudy mat;
    try {
        mat = prepare_matrix(m, delta);
    } catch (const NotDefinite& e) {
        (void)e;
        throw UsageError(
            "--mesh=" + o.mesh + " --delta=" + o.delta +
            ": A is not positive definite (CHOLMOD met a non-positive pivot), so it has no Cholesky factor; δ deepens "
            "the well, "
            "and at this one the lowest eigenvalue is negative: give a smaller δ (the default 0.05 gives 88.3)");
    }
    const Csr& a = mat.a;
    CommandFrame frame("suite");
    OutputDir* out = o.out.empty() ? nullptr
                                   : &frame.claim_dir(o.out, DirPolicy{.option = "--out",
                                                                       .command = "suite matrix",
                                                                       .inputs = inputs,
                                                                       .replace_earlier = o.replace});

    std::printf(
        "mesh %s: %zu triangles, %lld rows, %llu nonzeros; A at δ = %g; SpMV on %d thread(s), medians of %d\n\n",
        o.mesh.c_str(), m.elements(), static_cast<long long>(a.n), static_cast<unsigned long long>(a.nnz()), delta,
        o.threads, o.reps);
    std::printf("%-8s %10s %10s %14s %13s %11s %11s %11s %11s\n", "ordering", "order ms", "bandwidth", "profile",
                "nnz(L)", "GFlop", "factor ms", "solve ms", "SpMV ms");
    nlohmann::json doc = {
        {"mesh", o.mesh},
        {"triangles", m.elements()},
        {"rows", a.n},
        {"nonzeros", a.nnz()},
        {"delta", delta},
        {"matrix",
         "A = K - k² M (the fem kernels' stiffness matrix), symmetric positive definite here; each upper entry set to "
         "its lower twin, from which assembly's summation order made it differ by round-off"},
        {"asymmetry_removed", mat.asymmetry},
        {"threads_spmv", o.threads},
        {"reps", o.reps},
        {"seed", o.seed},
        {"libraries", nlohmann::json::object()},
        {"complete", false},
        {"orderings", nlohmann::json::array()}};
    for (const auto& [lib, version] : sparse_lib_versions()) doc["libraries"][lib] = version;
    // Both files after every ordering: an interrupted study keeps the ones it finished.
    const auto save = [&](const std::vector<OrderingStudy>& rows) {
        if (!out) return;
        out->write("matrix.md", markdown(o, a, rows));
        out->write("matrix.json", doc.dump(1) + "\n");
    };

    StudySettings settings;
    settings.reps = o.reps;
    settings.threads = o.threads;
    settings.max_factor_bytes = max_factor;
    settings.seed = o.seed;
    settings.spy_bins = spy_bins;
    std::vector<OrderingStudy> rows;
    for (const auto& name : orderings) {
        if (frame.stop_requested()) break;  // the safe point: between orderings
        OrderingStudy r = study_ordering(mat, m, name, settings);
        nlohmann::json entry = ordering_json(r, o);
        if (out && !o.exports.empty()) {
            const std::string file = name + ".mtx";
            out->write(file, matrix_market(r.permuted, {"suite matrix: A of " + o.mesh + " at delta " + o.delta +
                                                        ", vertices in " + name + " order"}));
            entry["export"] = file;
        }
        r.permuted = Csr{};  // written; not kept for the rest of the study
        doc["orderings"].push_back(entry);
        std::printf("%-8s %10.1f %10llu %14llu %13.0f %11.3f %11s %11s %11.3f\n", name.c_str(), 1e3 * r.order_s,
                    static_cast<unsigned long long>(r.structure.bandwidth),
                    static_cast<unsigned long long>(r.structure.profile), r.symbolic.factor_nnz, r.symbolic.flops / 1e9,
                    r.factorised ? fmt("%.1f", 1e3 * r.factor_median_s).c_str() : "-",
                    r.factorised ? fmt("%.2f", 1e3 * r.solve_median_s).c_str() : "-", 1e3 * r.spmv_median_s);
        std::fflush(stdout);
        rows.push_back(std::move(r));
        if (rows.size() < orderings.size()) save(rows);
    }
    for (const auto& r : rows)
        if (!r.factorised)
            std::printf("%s: factor analysed, not computed (%s)\n", r.name.c_str(),
                        r.factor_over_memory ? "twice its size is more than the memory available"
                                             : ("over --max-factor=" + o.max_factor).c_str());
    const std::string done = std::to_string(rows.size()) + " of " + std::to_string(orderings.size()) + " ordering(s)";
    const bool complete = rows.size() == orderings.size();
    doc["complete"] = complete;
    if (!out) return frame.finish(0, done, complete);
    save(rows);
    if (!complete) {
        std::printf("\nwrote %s (matrix.json, matrix.md; %s, incomplete: interrupted)\n", o.out.c_str(), done.c_str());
        return frame.finish(0, done, complete);
    }
    std::string pngs = "";
    if (!o.no_png) {
        const Plotter p = find_plotter("matrix.py");
        const std::string why =
            p.reason.empty() ? out->with_writer([&p](const std::string& dir) { return draw(p, dir); }) : p.reason;
        if (why.empty())
            pngs = ", spy-ORDERING.png, spy.png";
        else
            std::cerr << "suite: note: no spy plots: " << why << "\n";
    }
    std::printf("\nwrote %s (matrix.json, matrix.md%s%s)\n", o.out.c_str(), pngs.c_str(),
                o.exports.empty() ? "" : ", ORDERING.mtx");
    return frame.finish(0, done, complete);
}

}  // namespace suite
