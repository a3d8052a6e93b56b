// The suite's CSR SpMV against Eigen's sparse matrix-vector product, on the same P1 Helmholtz
// matrix A (δ = 0.05), the same x and the same thread count:
//   ours   #pragma omp parallel { b = my_block(n); spmv_rows(A, x, y, b.lo, b.hi); }  (fem-spmv's loop)
//   Eigen  y.noalias() = A * x;   A a Map<const SparseMatrix<double, RowMajor, int>> over the same
//                                 values, with int copies of row_ptr and col (made once, untimed)
// Both share the values and x; GB/s counts the minimal traffic of either: 12 B a nonzero, 4 B a row
// pointer, 8 B a row of x and 8 of y. (Eigen 3.4 moves more: its `=` zeroes y on one thread, then
// adds A x into it, 16 B a row more; that is its cost, not counted.) The two y must agree before
// anything is timed; then the two products alternate (ours, Eigen, ours, ...), the first call of
// each a warm-up.
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

// Without OpenMP Eigen's product would run on one thread whatever --threads says.
#ifndef EIGEN_HAS_OPENMP
#error "suite-spmv-eigen needs OpenMP (-fopenmp): Eigen runs its row-major sparse product in parallel only with it"
#endif

namespace {

using namespace suite;
using EigenCsr = Eigen::SparseMatrix<double, Eigen::RowMajor, int>;
using Clock = std::chrono::steady_clock;

constexpr double delta = 0.05;       // fem-spmv's default δ
constexpr double tolerance = 1e-12;  // per entry, relative
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
        return {{"best_s", t.min}, {"median_s", t.median}, {"best_gbs", bytes / t.min / 1e9}, {"median_gbs", bytes / t.median / 1e9}};
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
    // for both sides (the machine this was written for has one NUMA node).
    std::vector<double> x(static_cast<std::size_t>(n)), ours(x.size()), theirs(x.size());
    for (std::int64_t i = 0; i < n; ++i) x[i] = 1.0 + 0.5 * m.x[i] - 0.25 * m.y[i];
    const Eigen::Map<const Eigen::VectorXd> ex(x.data(), n);
    Eigen::Map<Eigen::VectorXd> ey(theirs.data(), n);

    const double* const xv = x.data();
    const double* const av = a.a.data();
    double* const yv = ours.data();
    int team = 0;
    auto run_ours = [&] {
        const auto t0 = Clock::now();
#pragma omp parallel
        {
            const Block b = my_block(n);
            fem::spmv_rows(p, av, xv, yv, b.lo, b.hi);
#pragma omp master
            team = omp_get_num_threads();
        }
        return std::chrono::duration<double>(Clock::now() - t0).count();
    };
    auto run_eigen = [&] {
        const auto t0 = Clock::now();
        ey.noalias() = ea * ex;
        return std::chrono::duration<double>(Clock::now() - t0).count();
    };

    run_ours();
    run_eigen();
    if (team != o.threads) throw UsageError("--threads=" + std::to_string(o.threads) + ": OpenMP gave a team of " + std::to_string(team));
    double worst = 0;
    std::int64_t worst_row = 0;
    for (std::int64_t i = 0; i < n; ++i) {
        const double scale = std::max(std::fabs(ours[i]), std::fabs(theirs[i]));
        const double rel = scale == 0 ? 0 : std::fabs(ours[i] - theirs[i]) / scale;
        if (rel > worst || std::isnan(rel)) worst = rel, worst_row = i;
    }
    if (!(worst <= tolerance)) {
        std::fprintf(stderr, "suite-spmv-eigen: %s: y differs at row %lld: ours %.17g, Eigen %.17g (relative %.3g > %.0e)\n",
                     ordering.c_str(), static_cast<long long>(worst_row), ours[worst_row], theirs[worst_row], worst, tolerance);
        std::exit(1);
    }

    std::vector<double> t_ours, t_eigen;
    for (int r = 0; r < o.reps; ++r) {
        t_ours.push_back(run_ours());
        t_eigen.push_back(run_eigen());
    }
    const Side so{summarise(t_ours)}, se{summarise(t_eigen)};
    const double bytes = fem::csr_bytes(nnz, n) + 16.0 * static_cast<double>(n);
    const double ratio = so.t.median / se.t.median;
    std::printf("%-8s %10.2f %10.2f   %10.2f %10.2f   %6.3f   %.1e\n", ordering.c_str(), bytes / so.t.min / 1e9, bytes / so.t.median / 1e9,
                bytes / se.t.min / 1e9, bytes / se.t.median / 1e9, ratio, worst);
    std::fflush(stdout);
    return {{"ordering", ordering}, {"rows", n},          {"nnz", nnz}, {"bytes", bytes}, {"max_relative_difference", worst},
            {"ours", so.to_json(bytes)}, {"eigen", se.to_json(bytes)}, {"ratio_ours_over_eigen_median", ratio}};
}

int run(int argc, char** argv) {
    Options o;
    CLI::App app{"The suite's CSR SpMV (fem-spmv's loop) against Eigen's sparse matrix-vector product on the same matrix"};
    app.add_option("--mesh", o.mesh, "mesh spec (as suite's --mesh)")->capture_default_str();
    app.add_option("--ordering", o.orderings, "natural|random|morton|hilbert|rcm, or a comma list of them")->delimiter(',')->capture_default_str();
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
    for (const auto& ordering : o.orderings)
        if (std::find(std::begin(fem::fem_orderings), std::end(fem::fem_orderings), ordering) == std::end(fem::fem_orderings))
            throw UsageError("--ordering=" + ordering + ": expected natural, random, morton, hilbert or rcm, or a comma list of them");
    OutputFile out;
    if (!o.json.empty()) out = OutputFile::claim(o.json, "--json", {});

    omp_set_dynamic(0);
    omp_set_num_threads(o.threads);
    Eigen::setNbThreads(o.threads);
    char host[256] = {0};
    gethostname(host, sizeof host - 1);
    std::printf("suite-spmv-eigen on %s: mesh %s, %d thread(s) (Eigen: %d), %d repetitions each, Eigen %d.%d.%d\n", host, o.mesh.c_str(),
                o.threads, Eigen::nbThreads(), o.reps, EIGEN_WORLD_VERSION, EIGEN_MAJOR_VERSION, EIGEN_MINOR_VERSION);
    std::printf("GB/s of 12 B a nonzero + 4 B a row pointer + 16 B a row (x, y); ratio = median time ours / Eigen (>1: ours slower)\n");
    std::printf("%-8s %10s %10s   %10s %10s   %6s   %s\n", "ordering", "ours best", "median", "Eigen best", "median", "ratio", "max rel diff");
    std::fflush(stdout);
    nlohmann::json results = nlohmann::json::array();
    for (const auto& ordering : o.orderings) results.push_back(compare(o, ordering));
    if (!o.json.empty()) {
        const nlohmann::json doc = {
            {"machine", {{"host", host}, {"threads", o.threads}, {"eigen_threads", Eigen::nbThreads()}, {"compiler", build::compiler}, {"compiler_flags", build::flags},
                         {"git_revision", build::git_revision}}},
            {"eigen_version", std::to_string(EIGEN_WORLD_VERSION) + "." + std::to_string(EIGEN_MAJOR_VERSION) + "." + std::to_string(EIGEN_MINOR_VERSION)},
            {"mesh", o.mesh},
            {"delta", delta},
            {"reps", o.reps},
            {"bytes_convention", "12 B a nonzero (8 value + 4 column index), 4 B a row pointer, 8 B a row of x and 8 of y; 1 GB = 1e9 B"},
            {"ratio", "median time ours / median time Eigen; > 1: ours slower"},
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
