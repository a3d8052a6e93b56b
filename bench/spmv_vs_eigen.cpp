// fem-spmv's products against Eigen's sparse matrix-vector product, on the same P1 Helmholtz
// matrix A (δ = 0.05), the same x and the same thread count, in one process:
//   plain      one row loop a thread, the loop fem-spmv had before its tuning (csr.hpp's spmv_rows)
//   csr        fem-spmv --strategy=csr: the same sums, the row loop unrolled by 4 (solver.hpp)
//   symmetric  fem-spmv --strategy=symmetric: one triangle, the window scheme (symmetric.hpp)
//   sell       fem-spmv --strategy=sell: SELL-C-σ at the default σ (sell.hpp)
//   Eigen      y.noalias() = A * x;   A a Map<const SparseMatrix<double, RowMajor, int>> over the same
//              values, with int copies of row_ptr and col (made once, untimed)
// GB/s counts the minimal traffic of each: its matrix bytes, 8 B a row of x and 8 of y (CSR and
// Eigen: 12 B a nonzero and 4 B a row pointer; symmetric: its own structure, about 7.5 B a
// nonzero; sell: CSR's, its padding a cost and not a credit, as fem-spmv counts it). (Eigen 3.4 moves more: its `=`
// zeroes y on one thread, then adds A x into it, 16 B a row more; that is its cost, not counted.) Every y must agree
// with Eigen's before anything is timed, to 1e-12 of the row's Σ|a_ij x_j|; then the five products
// alternate, the first call of each a warm-up. The ratios are of median times.
//   suite-spmv-eigen                                    the thesis mesh, hilbert, 1 thread
//   suite-spmv-eigen --ordering=natural,hilbert,rcm --threads=2 --json=spmv.json
#include <omp.h>
#include <unistd.h>

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "app/suite/parse.hpp"
#include "harness/common/output_file.hpp"
#include "harness/common/stats.hpp"
#include "harness/common/units.hpp"
#include "harness/kernel/blocks.hpp"
#include "harness/results/build_info.hpp"
#include "kernels/fem/assembly.hpp"
#include "kernels/fem/csr.hpp"
#include "kernels/fem/fem_mesh.hpp"
#include "kernels/fem/fem_point.hpp"
#include "kernels/fem/sell.hpp"
#include "kernels/fem/solver.hpp"
#include "kernels/fem/symmetric.hpp"

// Without OpenMP Eigen's product would run on one thread whatever --threads says.
#ifndef EIGEN_HAS_OPENMP
#error "suite-spmv-eigen needs OpenMP (-fopenmp): Eigen runs its row-major sparse product in parallel only with it"
#endif

namespace {

using namespace suite;
using EigenCsr = Eigen::SparseMatrix<double, Eigen::RowMajor, int>;
using Clock = std::chrono::steady_clock;

constexpr double delta = 0.05;       // fem-spmv's default δ
constexpr double tolerance = 1e-12;  // per entry, relative to the row's Σ|a_ij x_j|
constexpr std::uint64_t seed = 1;    // the suite's default --seed (the random ordering)

struct Options {
    std::string mesh = "file:../shared/meshes/unit_circle_fine.txt:refine=3";
    std::vector<std::string> orderings{"hilbert"};
    int threads = 1;
    int reps = 50;
    std::string json;
};

struct Side {
    TimeStats t;
    nlohmann::json to_json(double bytes) const {
        return {{"best_s", t.min},
                {"median_s", t.median},
                {"best_gbs", bytes / t.min / 1e9},
                {"median_gbs", bytes / t.median / 1e9}};
    }
};

// One ordering: both products checked against each other, then timed. Exit status 1 on a mismatch.
nlohmann::json compare(const Options& o, const std::string& ordering) {
    const mesh::Mesh m = fem::load_fem_mesh(o.mesh, ordering, seed);
    const std::int64_t n = static_cast<std::int64_t>(m.vertices());
    const fem::MeshArrays arrays{n, static_cast<std::int64_t>(m.elements()), m.x.data(), m.y.data(), m.conn.data()};
    fem::AssembledCsr a = fem::assemble_reference(arrays, delta);
    const fem::Pattern p = a.pattern();
    const std::uint64_t nnz = p.nnz();
    if (nnz > static_cast<std::uint64_t>(std::numeric_limits<int>::max()))
        throw UsageError("--mesh=" + o.mesh + ": " + std::to_string(nnz) + " nonzeros do not fit Eigen's int indices");
    const std::vector<int> rp(a.row_ptr.begin(), a.row_ptr.end()), col(a.col.begin(), a.col.end());
    const Eigen::Map<const EigenCsr> ea(n, n, static_cast<Eigen::Index>(nnz), rp.data(), col.data(), a.a.data());

    // fem-spmv's x: a smooth field. Every array here is first touched by the main thread, the same
    // for every side (the machine this was written for has one NUMA node).
    std::vector<double> x(static_cast<std::size_t>(n)), theirs(x.size()), scale(x.size());
    for (std::int64_t i = 0; i < n; ++i) x[i] = 1.0 + 0.5 * m.x[i] - 0.25 * m.y[i];
    for (std::int64_t i = 0; i < n; ++i)
        for (std::uint32_t k = p.row_ptr[i]; k < p.row_ptr[i + 1]; ++k) scale[i] += std::fabs(a.a[k] * x[p.col[k]]);
    const Eigen::Map<const Eigen::VectorXd> ex(x.data(), n);
    Eigen::Map<Eigen::VectorXd> ey(theirs.data(), n);
    const fem::SymmetricMatrix sym = fem::make_symmetric(p, a.a.data(), o.threads, fem::default_window);
    const fem::SellMatrix sell = fem::make_sell(p, a.a.data(), o.threads, fem::sell_default_sigma);
    const fem::Operator csr_op = fem::Operator::of_csr(p, a.a.data()),
                        sym_op = fem::Operator::of_symmetric(sym.pattern, sym.values()),
                        sell_op = fem::Operator::of_sell(sell.pattern, sell.val.data());

    const double* const xv = x.data();
    const double* const av = a.a.data();
    int team = 0;
    struct Candidate {
        const char* name;
        double bytes;
        std::vector<double> y;
        std::vector<double> times;
    };
    const double vectors = 16.0 * static_cast<double>(n);
    std::vector<Candidate> sides = {{"plain", fem::csr_bytes(nnz, n) + vectors, {}, {}},
                                    {"csr", fem::csr_bytes(nnz, n) + vectors, {}, {}},
                                    {"symmetric", sym.pattern.counts.matrix_bytes() + vectors, {}, {}},
                                    {"eigen", fem::csr_bytes(nnz, n) + vectors, {}, {}},
                                    {"sell", fem::csr_bytes(nnz, n) + vectors, {}, {}}};
    for (auto& c : sides) c.y.assign(static_cast<std::size_t>(n), 0.0);
    auto run_side = [&](std::size_t which) {
        double* const yv = which == 3 ? theirs.data() : sides[which].y.data();
        const auto t0 = Clock::now();
        if (which == 3) {
            ey.noalias() = ea * ex;
        } else {
#pragma omp parallel
            {
                const Block b = my_block(n);
                if (which == 0) fem::spmv_rows(p, av, xv, yv, b.lo, b.hi);
                if (which == 1) csr_op.apply(xv, yv, b);
                if (which == 2) sym_op.apply(xv, yv, b);
                if (which == 4) sell_op.apply(xv, yv, b);
#pragma omp master
                team = omp_get_num_threads();
            }
        }
        return std::chrono::duration<double>(Clock::now() - t0).count();
    };

    for (std::size_t s = 0; s < sides.size(); ++s) run_side(s);
    if (team != o.threads)
        throw UsageError("--threads=" + std::to_string(o.threads) + ": OpenMP gave a team of " + std::to_string(team));
    sides[3].y = theirs;
    double worst = 0;
    for (std::size_t s = 0; s < sides.size(); ++s)
        for (std::int64_t i = 0; i < n && s != 3; ++i) {  // 3: Eigen's own
            const double got = sides[s].y[i],
                         rel = scale[i] == 0 ? std::fabs(got - theirs[i]) : std::fabs(got - theirs[i]) / scale[i];
            worst = std::max(worst, rel);
            if (!(rel <= tolerance)) {
                std::fprintf(stderr,
                             "suite-spmv-eigen: %s: %s's y differs from Eigen's at row %lld: %.17g against %.17g (%.3g "
                             "of the row's sum of |a x| > %.0e)\n",
                             ordering.c_str(), sides[s].name, static_cast<long long>(i), got, theirs[i], rel,
                             tolerance);
                std::exit(1);
            }
        }

    for (int r = 0; r < o.reps; ++r)
        for (std::size_t s = 0; s < sides.size(); ++s) sides[s].times.push_back(run_side(s));
    nlohmann::json out = {
        {"ordering", ordering},
        {"rows", n},
        {"nnz", nnz},
        {"max_relative_difference", worst},
        {"symmetric_window", sym.pattern.counts.window},
        {"sell_c", fem::sell_c},
        {"sell_sigma", sell.pattern.counts.sigma},
        {"sell_padding", static_cast<double>(sell.pattern.counts.padding()) / static_cast<double>(nnz)},
        {"symmetric_far_entries", static_cast<double>(sym.pattern.counts.far_nnz) / static_cast<double>(nnz)}};
    std::vector<double> med;
    std::printf("%-8s", ordering.c_str());
    for (auto& c : sides) {
        const Side side{summarise(c.times)};
        med.push_back(side.t.median);
        out[c.name] = side.to_json(c.bytes);
        out[c.name]["bytes"] = c.bytes;
        std::printf(" %9.2f", c.bytes / side.t.median / 1e9);
    }
    const double csr_vs_plain = med[0] / med[1], sym_vs_csr = med[1] / med[2], csr_vs_eigen = med[3] / med[1],
                 sell_vs_csr = med[1] / med[4], sell_vs_eigen = med[3] / med[4];
    out["speedup_csr_over_plain"] = csr_vs_plain;
    out["speedup_symmetric_over_csr"] = sym_vs_csr;
    out["speedup_csr_over_eigen"] = csr_vs_eigen;
    out["speedup_sell_over_csr"] = sell_vs_csr;
    out["speedup_sell_over_eigen"] = sell_vs_eigen;
    std::printf("   %8.3f %8.3f %8.3f %8.3f %9.3f   %.1e\n", csr_vs_plain, sym_vs_csr, csr_vs_eigen, sell_vs_csr,
                sell_vs_eigen, worst);
    std::fflush(stdout);
    return out;
}

int run(int argc, char** argv) {
    Options o;
    CLI::App app{
        "fem-spmv's products (plain and tuned CSR, symmetric, SELL-C-σ) against Eigen's sparse matrix-vector product "
        "on the same matrix"};
    app.add_option("--mesh", o.mesh, "mesh spec (as suite's --mesh)")->capture_default_str();
    app.add_option("--ordering", o.orderings, fem::fem_orderings().accepted() + ", or a comma list of them")
        ->delimiter(',')
        ->capture_default_str();
    add_whole_option(app, "--threads", o.threads, 1, 1024, "OpenMP threads for both (default 1)");
    add_whole_option(app, "--reps", o.reps, 1, 1000000, "timed products of each, after one warm-up each (default 50)");
    app.add_option("--json", o.json, "also write the results to this JSON file");
    const std::vector<std::string> args(argv + 1, argv + argc);
    try {
        if (!parse_command_line(app, argv[0], args)) return 0;
    } catch (const CLI::ParseError& e) {
        throw UsageError(e.what());
    }
    // Before the minutes of loading and assembly, not after them.
    for (const auto& ordering : o.orderings) fem::fem_orderings().at(ordering);
    OutputFile out;
    if (!o.json.empty()) out = OutputFile::claim(o.json, "--json", {});

    omp_set_dynamic(0);
    omp_set_num_threads(o.threads);
    Eigen::setNbThreads(o.threads);
    char host[256] = {0};
    gethostname(host, sizeof host - 1);
    std::printf("suite-spmv-eigen on %s: mesh %s, %d thread(s) (Eigen: %d), %d repetitions each, Eigen %d.%d.%d\n",
                host, o.mesh.c_str(), o.threads, Eigen::nbThreads(), o.reps, EIGEN_WORLD_VERSION, EIGEN_MAJOR_VERSION,
                EIGEN_MINOR_VERSION);
    std::printf(
        "median GB/s of each format's minimal traffic; speed-ups are ratios of median times (> 1: the first is "
        "faster)\n");
    std::printf("%-8s %9s %9s %9s %9s %9s   %8s %8s %8s %8s %9s   %s\n", "ordering", "plain", "csr", "symmetric",
                "Eigen", "sell", "csr/plain", "sym/csr", "csr/Eigen", "sell/csr", "sell/Eigen", "max rel diff");
    std::fflush(stdout);
    nlohmann::json results = nlohmann::json::array();
    for (const auto& ordering : o.orderings) results.push_back(compare(o, ordering));
    if (!o.json.empty()) {
        const nlohmann::json doc = {
            {"machine",
             {{"host", host},
              {"threads", o.threads},
              {"eigen_threads", Eigen::nbThreads()},
              {"compiler", build::compiler},
              {"compiler_flags", build::flags},
              {"git_revision", build::git_revision}}},
            {"eigen_version", std::to_string(EIGEN_WORLD_VERSION) + "." + std::to_string(EIGEN_MAJOR_VERSION) + "." +
                                  std::to_string(EIGEN_MINOR_VERSION)},
            {"mesh", o.mesh},
            {"delta", delta},
            {"reps", o.reps},
            {"bytes_convention",
             "CSR, Eigen and sell: 12 B a nonzero (8 value + 4 column index), 4 B a row pointer (sell's padding not "
             "counted); symmetric: its structure's bytes; "
             "all: 8 B a row of x and 8 of y; 1 GB = 1e9 B"},
            {"speedups", "ratios of median times, > 1: the named first is faster"},
            {"results", results}};
        out.write(doc.dump(2) + "\n");
    }
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    try {
        return run(argc, argv);
    } catch (const UsageError& e) {
        std::fprintf(stderr, "suite-spmv-eigen: %s\n", e.what());
        return 2;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "suite-spmv-eigen: %s\n", e.what());
        return 1;
    }
}
