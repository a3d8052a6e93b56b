// suite-mpi: `suite run` on every rank of an MPI job at once (issue 16). Each rank pins and
// places as suite does, inside its share of its host (job.hpp); every point starts on all
// ranks together and each repetition is synchronised (RunSettings::comm); rank 0 gathers every
// rank's record, adds the aggregate (results/ranks.hpp) and writes the one result file, after
// every point, so that a job that is stopped or loses a rank leaves a valid file that says
// "complete": false. Exit status as suite's: 0, 1 a verification failed on some rank, 2 usage,
// 3 a solver did not converge, 128+N a signal; a rank that fails otherwise aborts the job
// (MPI_Abort) rather than leave the others waiting.
#include <mpi.h>
#include <signal.h>

#include <atomic>
#include <cstdio>
#include <iostream>
#include <set>

#include "app/suite-mpi/job.hpp"
#include "app/suite-mpi/mpi_comm.hpp"
#include "app/suite/data_dir.hpp"
#include "app/suite/defaults.hpp"
#include "app/suite/frame.hpp"
#include "app/suite/parse.hpp"
#include "app/suite/run.hpp"
#include "harness/common/output_file.hpp"
#include "harness/measure/output_formats.hpp"
#include "harness/results/context.hpp"
#include "harness/results/ranks.hpp"
#include "harness/results/report.hpp"
#include "rapl/energy.hpp"

namespace suite {
namespace {

const char* const mpi_examples = R"(
suite-mpi takes the options of `suite run` (above) and runs them on every rank of the job.
Each host's ranks share its CPUs without overlap: one rank per NUMA node when there are as
many ranks as nodes (the documented layout), else equal runs of cores; a launcher that bound
the ranks to disjoint sets is followed. --threads=all and --pin then mean the rank's share.
The result file (rank 0 writes it; JSON only) holds every rank's record of each point and an
aggregate: the ranks' work over the slowest rank's time per repetition, the slowest rank, the
spread between ranks. `suite compare FILE` lines up its hosts; `suite check` gates on it.

Examples:
  mpirun -np 2 ./suite-mpi --kernel=triad --size=1GiB --out=triad-mpi.json   # one rank per NUMA node on a 2-socket host
  mpirun -np 4 --map-by ppr:2:node ./suite-mpi --kernel=triad,add --size=512MiB --out=cluster.json
  srun -n 8 ./suite-mpi --kernel=fem-cg-dist --mesh=file:../shared/meshes/unit_circle_fine.txt:refine=3 --ordering=hilbert
  mpirun --allow-run-as-root --oversubscribe -np 2 ./suite-mpi --kernel=copy --size=64MiB   # as root, on a small machine

Exit status: 0 ok, 1 a kernel failed verification on some rank, 2 bad usage (said once, by rank 0),
3 a solver did not converge, 130/143 interrupted (the file holds the finished points, "complete": false).
)";

std::string fmt_spread(double x) {
    char text[32];
    std::snprintf(text, sizeof text, "%.3f", x);
    return text;
}

// Thrown on every rank for a decision rank 0 took and has already said (exit `status`).
struct Quiet : std::exception {
    int status;
    explicit Quiet(int s) : status(s) {}
};

// Runs `decide` on rank 0; its UsageError becomes every rank's exit 2, said once.
template <class F>
void on_rank0(const Job& job, F&& decide) {
    std::string refusal;
    if (job.rank == 0) try {
            decide();
        } catch (const UsageError& e) {
            refusal = e.what();
        } catch (const CLI::ParseError& e) {
            refusal = std::string(e.what()) + " (see ./suite-mpi --help)";
        }
    refusal = broadcast_text(refusal);
    if (!refusal.empty()) {
        if (job.rank == 0) std::cerr << "suite-mpi: error: " << refusal << "\n";
        throw Quiet(2);
    }
}

// Runs `decide` on every rank (a rank's share of its host may refuse what rank 0's accepts:
// --pin=0 on a rank whose CPUs do not include 0); the first refusal, by rank, becomes every
// rank's exit 2, said once by rank 0 with the rank that found it.
template <class F>
void on_every_rank(const Job& job, F&& decide) {
    std::string refusal;
    try {
        decide();
    } catch (const UsageError& e) {
        refusal = e.what();
    }
    const std::vector<std::string> all = gather_texts(refusal);
    std::string first;
    if (job.rank == 0)
        for (std::size_t r = 0; r < all.size() && first.empty(); ++r)
            if (!all[r].empty()) first = (r == 0 ? "" : "rank " + std::to_string(r) + ": ") + all[r];
    first = broadcast_text(first);
    if (!first.empty()) {
        if (job.rank == 0) std::cerr << "suite-mpi: error: " << first << "\n";
        throw Quiet(2);
    }
}

int run_job(const std::vector<std::string>& args, const std::vector<std::string>& argv) {
    const Job job = start_job();
    const MpiComm comm;
    CLI::App app{"suite-mpi: suite's kernels on every rank of an MPI job, with verified results"};
    app.footer(mpi_examples);
    app.get_formatter()->column_width(28);
    RunOptions opts;
    setup_run_options(app, opts);
    if (job.rank != 0) std::cout.rdbuf(nullptr);  // the help and the table: once, from rank 0
    bool go = true;
    on_rank0(job, [&] { go = parse_command_line(app, "suite-mpi", args); });
    if (job.rank != 0) parse_command_line(app, "suite-mpi", args);
    if (broadcast_text(go ? "go" : "").empty()) return 0;  // --help was printed
    const Topology topo = Topology::load();                // this rank's share
    Plan plan;
    on_every_rank(job, [&] {
        plan = make_plan(opts, topo, open_energy);
        if (plan.format != OutputFormat::json && !(plan.format == OutputFormat::table && plan.out_path.empty()))
            throw UsageError("--format=" + format_name(plan.format) +
                             ": suite-mpi writes JSON (a file with --out, or the table on the console)");
    });
    if (job.rank == 0 && !plan.dry_run)
        for (const auto& note : plan.notes) std::cerr << "suite-mpi: note: " << note << "\n";
    // Every rank stops at the same sample once any rank is asked to (the runner agrees on it),
    // so a second signal waits for that rather than leave the others in a collective.
    CommandFrame frame("suite-mpi", CommandFrame::SecondSignal::waits_for_ranks);
    on_rank0(job, [&] {
        if (!plan.out_path.empty()) frame.claim_file(plan.out_path, "--out", run_inputs(opts));
    });
    if (plan.dry_run) return job.rank == 0 ? execute_plan(plan, topo, argv, frame) : 0;
    const OutputFile* out = frame.file();

    plan.settings.stop = frame.stop_flag();
    plan.settings.instruments = &plan.instruments;
    plan.settings.comm = &comm;

    nlohmann::json doc;
    const bool to_file = !plan.out_path.empty();
    if (job.rank == 0) {
        doc = {{"schema_version", schema_version}, {"complete", false}, {"results", nlohmann::json::array()}};
        doc["context"] = build_context(topo, argv, plan.instruments, bandwidth_convention());
        doc["context"]["mpi"] = job.context;
        if (to_file) out->write(doc.dump(1) + "\n");  // valid from the start: a job killed at once leaves this
        if (!plan.quiet) std::cout << table_header() << std::flush;
    }
    int status = 0;
    bool interrupted = false;
    const std::size_t total = plan.points.size();
    for (std::size_t i = 0; i < total; ++i) {
        Record rec;
        try {
            rec = run_point(plan.points[i], plan.settings, topo);
        } catch (const Interrupted&) {
            interrupted = true;  // every rank stops at the same sample (runner.cpp, sync_ranks)
            break;
        }
        rec.mpi.kind = RankScope::Kind::rank;
        rec.mpi.rank = job.rank;
        rec.mpi.ranks = job.size;
        rec.mpi.host = job.host;
        const std::vector<std::string> texts = gather_texts(to_json(rec).dump());
        if (job.rank != 0) continue;
        std::vector<RankRun> runs;
        for (const auto& t : texts) {
            nlohmann::json j = nlohmann::json::parse(t);
            runs.push_back(rank_run_from_json(j));
            doc["results"].push_back(std::move(j));
        }
        const Record all = aggregate_record(rec, runs, job.hosts);
        doc["results"].push_back(to_json(all));
        if (to_file) out->write(doc.dump(1) + "\n");
        for (const RankRun& r : runs)
            if (r.solver_failed)
                status = 3;
            else if (!r.passed && status == 0)
                status = 1;
        if (!all.verification.passed)
            std::cerr << "suite-mpi: error: " << all.name << " " << all.access
                      << " failed verification: " << all.verification.detail << "\n";
        if (!plan.quiet) {
            std::cout << table_row(i + 1, total, all);
            std::cout << "        " << runs.size() << " ranks on " << job.hosts << " host(s); slowest rank "
                      << all.mpi.slowest_rank << " (" << all.mpi.slowest_host << "), best times spread "
                      << fmt_spread(all.mpi.spread) << "x\n"
                      << std::flush;
        }
    }
    const int stopped_by =
        static_cast<int>(comm.max(interrupted ? frame.stop_signal() : 0));  // the signal, as some rank got it
    const int result = static_cast<int>(comm.max(interrupted ? 128 + stopped_by : status));
    if (job.rank == 0) {
        doc["complete"] = !interrupted;
        if (to_file) {
            out->write(doc.dump(1) + "\n");
            if (!plan.quiet)
                std::cerr << "wrote " << doc["results"].size() << " record(s) to " << plan.out_path << "\n";
        } else if (plan.format == OutputFormat::json) {
            std::cout << doc.dump(1) << "\n";
        }
        if (interrupted)
            std::cerr << "suite-mpi: interrupted by signal " << stopped_by << " after "
                      << doc["results"].size() / (job.size + 1) << " of " << total << " point(s)\n";
    }
    return result;
}

}  // namespace
}  // namespace suite

int main(int argc, char** argv) {
    using namespace suite;
    if (argc == 2 && std::string(argv[1]) == "--version") {
        // Before MPI_Init: the version needs no job (MPI_Get_library_version may be called first).
        char library[MPI_MAX_LIBRARY_VERSION_STRING];
        int length = 0;
        MPI_Get_library_version(library, &length);
        std::string mpi(library, static_cast<std::size_t>(length));
        mpi = mpi.substr(0, mpi.find_first_of(",\n"));
        std::cout << version_text("suite-mpi") << "MPI: " << mpi << "\n";
        return 0;
    }
    signal(SIGXFSZ, SIG_IGN);
    int provided = 0;
    MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided);
    int rank = 0;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    std::vector<std::string> all(argv, argv + argc);
    std::vector<std::string> args(all.begin() + 1, all.end());
    if (!args.empty() && args[0] == "run") args.erase(args.begin());
    int status = 0;
    try {
        status = run_job(args, all);
    } catch (const Quiet& q) {
        status = q.status;
    } catch (const JobRefused& e) {
        if (rank == 0) std::cerr << "suite-mpi: error: " << e.message << "\n";
        status = 2;
    } catch (const std::exception& e) {
        // One rank alone: the others may be waiting for it in a collective. End the job.
        std::cerr << "suite-mpi: rank " << rank << ": error: " << e.what() << "; ending the job\n" << std::flush;
        MPI_Abort(MPI_COMM_WORLD, 1);
    }
    MPI_Finalize();
    return status;
}
