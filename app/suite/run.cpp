#include "app/suite/run.hpp"

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <map>
#include <stdexcept>

#include "app/suite/commands.hpp"
#include "app/suite/defaults.hpp"
#include "app/suite/frame.hpp"
#include "app/suite/parse.hpp"
#include "harness/common/output_file.hpp"
#include "harness/common/text.hpp"
#include "harness/common/units.hpp"
#include "harness/kernel/hugepage_modes.hpp"
#include "harness/kernel/store_variants.hpp"
#include "harness/measure/cache_probe.hpp"
#include "harness/measure/output_formats.hpp"
#include "harness/results/context.hpp"
#include "harness/results/report.hpp"
#include "kernels/mesh/mesh_spec.hpp"
#include "kernels/sfc/orderings.hpp"
#include "rapl/energy.hpp"

namespace suite {
namespace run_command {
namespace {

const char* const examples = R"(
Commands:
  run (default)   measure kernels: ./suite [run] --kernel=... [options]
  list            kernels, patterns, placements: ./suite list [--json] [--counters]
  info            topology, caches, NUMA nodes: ./suite info [--json] [--probe]
  compare         result files side by side: ./suite compare A.json B.json [--format=markdown]
  check           CI regression gate: ./suite check --baseline BASE.json RUN.json (exit 1: regressed)
  history         runs across commits in SQLite: ./suite history add|list|steps|check|html (see ./suite history --help)
  deterministic   exact instruction and simulated miss counts under valgrind (x86-64-v3 build)
  traverse        how a loop walks a mesh, per ordering: ./suite traverse --mesh=... --out=DIR (see ./suite traverse --help)
  matrix          the fem matrix per vertex ordering (bandwidth, Cholesky fill, SpMV): ./suite matrix --mesh=... --out=DIR
  mpm             the MPM dam collapse as a simulation, snapshots for ParaView: ./suite mpm --out=DIR (see ./suite mpm --help)
  roofline        this machine's measured ceilings, and a run placed on them: ./suite roofline [--out=FILE] [--place=RUN.json]
  --version       the version, git revision, compiler and flags, the parts this build has, where its data is

Examples:
  ./suite --kernel=add --pattern=random                   # the thesis's kernel 3, default sizes
  ./suite --kernel=add,sin-add --pattern=sequential,random --size=256MiB --threads=1,2
  ./suite --kernel=triad --sizes=16KiB:1GiB --threads=1-2 --out=results/triad.json
  ./suite --kernel=copy,triad --stores=nt --size=1GiB      # non-temporal stores
  ./suite --kernel=latency --sizes=4KiB:256MiB:x2 --threads=1
  ./suite --kernel=load,store --size=1GiB                  # one stream of loads, one of stores
  ./suite --kernel=store --stores=nt --size=1GiB           # streaming stores: no write-allocate
  ./suite --kernel=copy,store --stores=rep --size=1MiB     # rep movsb / rep stosq, as memcpy and memset
  ./suite --kernel=triad --size=1GiB --hugepages=thp       # arrays on transparent huge pages
  ./suite --probe-caches --kernel=triad                    # default sizes from the measured caches
  ./suite info --probe                                     # caches measured beside hwloc's
  ./suite --kernel=triad --placement=node:1 --pin=0,1 --threads=2   # arrays on node 1, threads on CPUs 0, 1
  ./suite --kernel=triad --placement=remote --threads=1    # arrays on another node than the thread's
  ./suite --kernel=triad --size=1GiB --counters=cycles,instructions,LLC-load-misses
  ./suite --kernel=add --pattern=random --energy=sysfs --energy-baseline=2   # energy above idle power
  ./suite --kernel=triad --sizes=16KiB:64MiB --format=gbench --out=triad-gb.json   # Google Benchmark's JSON
  ./suite compare results/a.json results/b.json            # two machines or builds (see ./suite compare --help)
  ./suite check --baseline results/baseline/ci.json run.json   # exit 1 on a regression
  build/suite-x86-64-v3 deterministic --kernel=add --out=det.json   # exact counts under valgrind
  plots/plot.py results/triad.json --out=figures/          # PNG figures (python3-matplotlib)
  ./suite --kernel=sfc-build --mesh=disk:refine=8 --ordering=morton,hilbert,morton-recursive,rcm --threads=1,2
  ./suite --kernel=sfc-build --mesh=box:64,64,64 --phase=keys,sort,renumber,all   # each phase timed as its own point
  ./suite --kernel=sfc-build --mesh=file:../shared/meshes/unit_circle_fine.txt:refine=3 --ordering=morton
  ./suite traverse --mesh=disk:refine=4 --ordering=natural,morton,hilbert --threads=1,4 --out=traverse

Exit status: 0 ok, 1 a kernel failed verification, 2 bad usage, 3 an iterative solver did not
converge (before 1), 130/143 interrupted (the result file then holds the finished points and says
"complete": false).
)";

// One option --NAME=X for every parameter a registered kernel declares (KernelInfo::params),
// collected now: CLI11 needs its options before it parses. The text is kept as typed and
// checked by make_plan, which knows the kernels selected.
void add_param_options(CLI::App& app, RunOptions& o) {
    std::map<std::string, std::string> help;  // the first kernel's help for each name
    for (const auto& e : kernels())
        for (const auto& p : e.info.params)
            if (!help.count(p.name)) help[p.name] = p.help;
    for (const auto& [name, text] : help) {
        const std::string option = "--" + name;
        if (app.get_option_no_throw(option))
            throw std::logic_error("a kernel declares the parameter '" + name +
                                   "', which is an option of suite run already");
        app.add_option_function<std::string>(
               option, [&o, name = name](const std::string& value) { o.params[name] = value; },
               text + "; " + param_users(name))
            ->type_name("X");
    }
}

std::string params_label(const Params& params) {
    std::string out;
    for (const auto& [name, value] : params) out += " " + name + "=" + param_text(value);
    return out;
}

// The names `--OPTION` gives variants, gathered from the kernels that take it (KernelInfo::
// variant_option), in the order they declare them: those kernels' choice tables, never a copy.
std::string variant_names(const std::string& option) {
    std::vector<std::string> names;
    for (const auto& e : kernels()) {
        if (e.info.variant_option != option) continue;
        for (const auto& v : e.info.variants)
            if (!v.empty() && !is_store_variant(v) && std::find(names.begin(), names.end(), v) == names.end())
                names.push_back(v);
    }
    return join(names, ", ");
}

// The access patterns of the kernels that walk memory in one (--pattern), in the order they declare
// them; a pattern whose label carries a stride (strided) shown as it is typed, strided:S.
std::string pattern_names() {
    std::vector<std::string> names;
    for (const auto& e : kernels()) {
        if (e.info.axis != AccessAxis::pattern) continue;
        for (const auto& a : e.info.accesses) {
            const std::string shown = Access{a, 1}.label() == a ? a : a + ":S";
            if (std::find(names.begin(), names.end(), shown) == names.end()) names.push_back(shown);
        }
    }
    return join(names, ", ");
}

// The writer of a format --out can hold (the console table is no file's format).
FileFormat file_format(OutputFormat f) {
    switch (f) {
        case OutputFormat::csv:
            return FileFormat::csv;
        case OutputFormat::gbench:
            return FileFormat::gbench;
        case OutputFormat::json:
        case OutputFormat::table:
            break;
    }
    return FileFormat::json;
}

}  // namespace
}  // namespace run_command

std::string param_users(const std::string& name) {
    std::vector<std::string> users, with_defaults, shown;
    for (const auto& e : kernels())
        for (const auto& p : e.info.params)
            if (p.name == name) {
                users.push_back(e.info.name);
                shown.push_back(param_text(default_params(e.info).at(name)));
                with_defaults.push_back(e.info.name + " (default " + shown.back() + ")");
            }
    if (users.empty()) return "";
    if (std::all_of(shown.begin(), shown.end(), [&](const std::string& d) { return d == shown.front(); }))
        return "default " + shown.front() + " (" + join(users, ", ") + ")";
    return join(with_defaults, ", ");
}

void setup_run_options(CLI::App& app, RunOptions& o) {
    o.default_sweep = default_sweep();
    app.add_option("--kernel,-k", o.kernels, "kernels, comma separated (see ./suite list); default: the default sweep");
    app.add_option("--pattern,-p", o.patterns,
                   "access patterns: " + run_command::pattern_names() + " (default: the kernel's first)");
    app.add_option("--ordering", o.orderings,
                   "data orderings of application kernels: " + sfc::mesh_orderings().accepted() +
                       " (those each takes: ./suite list; default: the kernel's first)");
    app.add_option("--mesh", o.mesh,
                   "mesh of kernels on a mesh: disk:refine=K | box:NX,NY,NZ[:refine=K] | file:PATH[:refine=K] (.msh or "
                   "thesis .txt)");
    app.add_option("--phase", o.phases,
                   "phases of sfc-build measured as separate points: " + run_command::variant_names("phase") +
                       ", all (default all)");
    app.add_option("--strategy", o.strategies,
                   "strategies of the kernels that have them, each measured as its own point (see ./suite list; "
                   "default: the kernel's own)");
    app.add_option("--particles", o.particles,
                   "particle orders of the MPM kernels, each its own point: " +
                       run_command::variant_names("particles") + " (default: all that the kernel has)");
    app.add_option("--isa", o.isas,
                   "instruction widths of peak-flops, each its own point: " + run_command::variant_names("isa") +
                       " (those this build targets; default: all)");
    run_command::add_param_options(app, o);
    app.add_option("--stores", o.stores, store_variants().described() + "; sequential only");
    app.add_option("--size", o.size, "footprint of all the kernel's arrays together, e.g. 64MiB");
    app.add_option("--sizes", o.sizes,
                   "sizes: a sweep FROM:TO[:xF] (e.g. 16KiB:1GiB, 16KiB:1GiB:x1.5) or a list 32KiB,1MiB");
    app.add_option("--threads,-t", o.threads, "thread counts: 1,2,4 | 1-8 | 1-8:2 | all (default: 1 and all)");
    app.add_option("--pin", o.pin,
                   pin_modes().described() + ", or a CPU list such as 0,2,4-7 (default: " + o.pin + ")");
    app.add_option("--placement", o.placement, placement_kinds().described() + " (default: " + o.placement + ")");
    app.add_flag(
        "--probe-caches", o.probe_caches,
        "measure the caches first (a few seconds; ./suite info --probe shows the same) and size the default sweep "
        "by the measured last level where it is smaller than the reported one");
    app.add_option("--hugepages", o.hugepages, hugepage_modes().described());
    add_whole_option(app, "--reps", o.reps, 1, 10000000,
                     "counted repetitions per point, 1 to 10000000 (default: enough for 0.2 s, at least 5; plus 1 "
                     "warm-up, 3 for calls under 50 ms)");
    app.add_option("--min-time", o.min_time,
                   "seconds of counted repetitions per point when --reps is not given (default 0.2)");
    app.add_flag("--fresh-arrays", o.fresh_arrays,
                 "each counted repetition after the first on the point's arrays allocated and first-touched anew, "
                 "then warmed by one uncounted call: the median is over as many page placements as repetitions, and "
                 "moves less from run to run where the placement sets the bandwidth (a CI gate's DRAM points here; "
                 "docs/noise.md). Off by default: one allocation, as STREAM and likwid-bench");
    add_seed_option(app, o.seed, "seed of the random permutations, 0 to 18446744073709551615 (default 1)");
    app.add_option("--out,-o", o.out, "write results to FILE (JSON, or CSV for *.csv or with --format=csv)");
    app.add_option("--format", o.format,
                   "format of --out, or of stdout without --out: " + output_formats().described());
    app.add_flag("--quiet,-q", o.quiet, "no table or progress on the console");
    app.add_flag("--dry-run", o.dry_run, "check the options, list the points that would run, and stop");
    app.add_option(
        "--counters", o.counters,
        "default | none | events, e.g. cycles,instructions,LLC-load-misses,page-faults (see ./suite list --counters)");
    app.add_option("--energy", o.energy,
                   "where RAPL energy is read: " + energy_backends().described() + " (default " + o.energy +
                       "; root: SUITE_SYSFS_ROOT)");
    app.add_option("--energy-baseline", o.energy_baseline,
                   "measure idle power for SECONDS first and report energy above idle");
}

std::vector<FileIdentity> run_inputs(const RunOptions& o) {
    std::vector<std::string> paths;
    if (!o.mesh.empty()) {
        const mesh::MeshSpec spec = mesh::parse_mesh_spec(o.mesh);
        if (spec.kind == mesh::MeshSpec::Kind::file) paths.push_back(spec.path);
    }
    return identify_inputs(paths);
}

int execute_plan(Plan& plan, const Topology& topo, const std::vector<std::string>& argv, CommandFrame& frame) {
    for (const auto& note : plan.notes) std::cerr << "suite: note: " << note << "\n";
    if (plan.dry_run) {
        std::cout << plan.points.size() << " point(s), pin=" << plan.settings.pin.text
                  << ", placement=" << plan.settings.placement.text
                  << (plan.out_path.empty() ? "" : ", output " + plan.out_path + " (" + format_name(plan.format) + ")")
                  << "\n";
        for (const auto& p : plan.points)
            std::cout << "  " << display_name(p.kernel->info.name, p.variant) << " " << p.access.label() << " "
                      << size_label(p.kernel->info.size_kind, p.size) << " threads=" << p.threads
                      << (p.mesh.empty() ? "" : " mesh=" + p.mesh) << run_command::params_label(p.params) << "\n";
        return 0;
    }
    plan.settings.stop = frame.stop_flag();
    plan.settings.instruments = &plan.instruments;
    if (plan.instruments.energy_baseline_s > 0 && plan.instruments.energy->available()) {
        if (!plan.quiet) std::cerr << "measuring idle power for " << plan.instruments.energy_baseline_s << " s ...\n";
        plan.instruments.energy->measure_idle(plan.instruments.energy_baseline_s);
    }

    const bool to_file = !plan.out_path.empty();
    const OutputFile* out = frame.file();
    if (to_file && (!out || out->path() != plan.out_path))
        throw std::logic_error("execute_plan: --out was not claimed");
    const bool console_table = !plan.quiet && (to_file || plan.format == OutputFormat::table);
    const bool progress = !plan.quiet && isatty(STDERR_FILENO);
    const FileFormat format = run_command::file_format(plan.format);
    ResultDocument doc{build_context(topo, argv, plan.instruments, bandwidth_convention()), {}};
    if (!plan.caches_measured.is_null()) doc.context["caches_measured"] = plan.caches_measured;

    if (console_table) std::cout << table_header() << std::flush;
    int status = 0;
    const std::size_t total = plan.points.size();
    for (std::size_t i = 0; i < total && !frame.stop_requested(); ++i) {
        const Point& p = plan.points[i];
        if (progress) {
            std::fprintf(stderr, "\r[%zu/%zu] %s %s %s threads=%d ...", i + 1, total,
                         display_name(p.kernel->info.name, p.variant).c_str(), p.access.label().c_str(),
                         size_label(p.kernel->info.size_kind, p.size).c_str(), p.threads);
            std::fflush(stderr);
        }
        Record rec;
        try {
            rec = run_point(p, plan.settings, topo);
        } catch (const Interrupted&) {
            break;
        } catch (...) {
            // The finished points are kept: in the file (already saved) or on stdout.
            if (progress) std::fprintf(stderr, "\r\033[K");
            if (!to_file && plan.format != OutputFormat::table) std::cout << doc.render(format, false) << std::flush;
            throw;
        }
        if (progress) std::fprintf(stderr, "\r\033[K");
        if (rec.verification.solver_failed) {
            std::cerr << "suite: error: " << rec.name << " " << rec.access << " "
                      << size_label(rec.size_kind, rec.size_requested) << ": solver failed: " << rec.verification.detail
                      << "\n";
            status = 3;  // before 1: a solver that did not converge says more than a wrong answer
        } else if (!rec.verification.passed) {
            std::cerr << "suite: error: " << rec.name << " " << rec.access << " "
                      << size_label(rec.size_kind, rec.size_requested)
                      << " failed verification: " << rec.verification.detail << "\n";
            if (status == 0) status = 1;
        }
        if (console_table) std::cout << table_row(i + 1, total, rec) << std::flush;
        doc.records.push_back(std::move(rec));
        if (to_file) out->write(doc.render(format, false), false);
    }
    if (progress) std::fprintf(stderr, "\r\033[K");
    if (console_table) std::cout << stability_summary(doc.records) << std::flush;
    // Complete when every point was measured, whenever a signal came.
    const bool complete = doc.records.size() == total;
    if (to_file) {
        const std::string wrote = out->write(doc.render(format, complete), complete);
        if (wrote != plan.out_path)
            std::cerr << "suite: note: " << plan.out_path << " holds a complete result and is kept; this run's "
                      << doc.records.size() << " record(s), incomplete, are in " << wrote << "\n";
        else if (!plan.quiet)
            std::cerr << "wrote " << doc.records.size() << " record(s) to " << plan.out_path
                      << (complete ? "" : " (incomplete: interrupted)") << "\n";
    } else if (plan.format != OutputFormat::table) {
        std::cout << doc.render(format, complete) << std::flush;
    }
    return frame.finish(status, std::to_string(doc.records.size()) + " of " + std::to_string(total) + " point(s)",
                        complete);
}

int cmd_run(const std::vector<std::string>& args, const std::vector<std::string>& full_argv) {
    CLI::App app{"suite: NUMA/cache micro-benchmarks with verified results"};
    app.footer(run_command::examples);
    app.get_formatter()->column_width(28);
    RunOptions opts;
    setup_run_options(app, opts);
    if (!parse_command_line(app, "suite", args)) return 0;
    const Topology topo = Topology::load();
    Plan plan = make_plan(opts, topo, open_energy);
    // Claimed before anything runs: a second run on the same file refuses now, not at the end.
    CommandFrame frame("suite");
    if (!plan.out_path.empty()) frame.claim_file(plan.out_path, "--out", run_inputs(opts));
    if (opts.probe_caches && !plan.dry_run) {
        // The options are all checked before the seconds of probing; the plan is then made again
        // with the measured last level, which only changes the default sizes.
        if (!plan.quiet) std::cerr << "probing the caches (suite info --probe) ...\n";
        ProbeOptions po = probe_options();
        po.hugepages = plan.settings.hugepages;
        const CacheProbe probe = probe_caches(topo, po);
        if (!plan.quiet) std::cerr << format_probe(probe, topo);
        opts.measured = measured_caches(probe, topo);
        plan = make_plan(opts, topo, open_energy);
        plan.caches_measured = to_json(probe, topo);
    }
    return execute_plan(plan, topo, full_argv, frame);
}

}  // namespace suite
