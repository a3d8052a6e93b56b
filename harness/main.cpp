// suite: the command line. main() only picks the command and maps errors to exit statuses:
// 0 success, 1 a kernel failed verification or the run failed, 2 a usage error, 128+N a signal.
#include <cstring>
#include <optional>
#include <iostream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "harness/check.hpp"
#include "harness/cli_parse.hpp"
#include "harness/cache_probe.hpp"
#include "harness/cli_counters.hpp"
#include "harness/cli_run.hpp"
#include "harness/compare.hpp"
#include "harness/instruments.hpp"
#include "harness/context.hpp"
#include "harness/deterministic.hpp"
#include "harness/kernel.hpp"
#include "harness/topology.hpp"
#include "harness/units.hpp"
#include "kernels/sfc/traverse.hpp"

namespace suite {
namespace {

const char* const examples = R"(
Commands:
  run (default)   measure kernels: ./suite [run] --kernel=... [options]
  list            kernels, patterns, placements: ./suite list [--json] [--counters]
  info            topology, caches, NUMA nodes: ./suite info [--json] [--probe]
  compare         result files side by side: ./suite compare A.json B.json [--format=markdown]
  check           CI regression gate: ./suite check --baseline BASE.json RUN.json (exit 1: regressed)
  deterministic   exact instruction and simulated miss counts under valgrind (x86-64-v3 build)
  traverse        how a loop walks a mesh, per ordering: ./suite traverse --mesh=... --out=DIR (see ./suite traverse --help)

Examples:
  ./suite --kernel=add --pattern=random                   # the thesis's kernel 3, default sizes
  ./suite --kernel=add,sin-add --pattern=sequential,random --size=256MiB --threads=1,2
  ./suite --kernel=triad --sizes=16KiB:1GiB --threads=1-2 --out=results/triad.json
  ./suite --kernel=copy,triad --stores=nt --size=1GiB      # non-temporal stores
  ./suite --kernel=latency --sizes=4KiB:256MiB:x2 --threads=1
  ./suite --kernel=load,store --size=1GiB                  # one stream of loads, one of stores
  ./suite --kernel=store --stores=nt --size=1GiB           # streaming stores: no write-allocate
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

Exit status: 0 ok, 1 a kernel failed verification, 2 bad usage, 130/143 interrupted (the
result file then holds the finished points and says "complete": false).
)";

bool parse(CLI::App& app, const char* name, const std::vector<std::string>& args) { return parse_command_line(app, name, args); }

std::string accesses_text(const KernelInfo& info) {
    std::string out;
    for (const auto& a : info.accesses) out += (out.empty() ? "" : ",") + (a == "strided" ? std::string("strided:S") : a);
    return out;
}

int cmd_list(const std::vector<std::string>& args) {
    CLI::App app{"suite list: the kernels and what they accept"};
    bool json = false, counters = false;
    app.add_flag("--json", json, "machine-readable output");
    app.add_flag("--counters", counters, "the events that can be counted here (generic and this PMU's), and why not");
    if (!parse(app, "suite list", args)) return 0;
    if (counters) return list_counters(json);
    if (json) {
        nlohmann::json j = nlohmann::json::array();
        for (const auto& e : kernels()) {
            const auto& i = e.info;
            j.push_back({{"name", i.name}, {"group", i.group}, {"formula", i.formula}, {"unit", i.unit},
                         {"axis", i.axis == AccessAxis::pattern ? "pattern" : "ordering"}, {"accesses", i.accesses},
                         {"variants", i.variants}, {"size", i.size_kind == SizeKind::bytes ? "bytes" : "count"},
                         {"metric", i.metric == Metric::bandwidth ? "bandwidth" : "latency"},
                         {"read_bytes_per_unit", i.read_bytes_per_unit}, {"write_bytes_per_unit", i.write_bytes_per_unit},
                         {"flops_per_unit", i.flops_per_unit}, {"notes", i.notes}});
        }
        std::cout << j.dump(2) << "\n";
        return 0;
    }
    std::printf("%-9s %-8s %-30s %-28s %-6s %-12s %s\n", "kernel", "group", "formula", "patterns/orderings", "nt", "B/unit r+w", "flops");
    for (const auto& e : kernels()) {
        const auto& i = e.info;
        char bytes[32];
        std::snprintf(bytes, sizeof bytes, "%g+%g", i.read_bytes_per_unit, i.write_bytes_per_unit);
        const bool nt = std::find(i.variants.begin(), i.variants.end(), "nt") != i.variants.end();
        std::printf("%-9s %-8s %-30s %-28s %-6s %-12s %g\n", i.name.c_str(), i.group.c_str(), i.formula.c_str(),
                    accesses_text(i).c_str(), nt ? "yes" : "-", bytes, i.flops_per_unit);
    }
    std::printf("\nPlacements: local (first touch by the computing threads), node:N, remote (a node none of the threads\n"
                "runs on), interleave (pages round-robin over all nodes).  Pinning: compact, scatter, none, CPU list.\n"
                "Counters: --counters=default|none|NAME,... (./suite list --counters).  Energy: --energy=auto|sysfs|perf|none.\n");
    return 0;
}

int cmd_info(const std::vector<std::string>& args) {
    CLI::App app{"suite info: the machine as hwloc sees it"};
    bool json = false, probe = false;
    app.add_flag("--json", json, "machine-readable output");
    app.add_flag("--probe", probe, "also measure the caches this process really gets (pointer chase and load bandwidth, a few seconds)");
    if (!parse(app, "suite info", args)) return 0;
    const Topology topo = Topology::load();
    std::optional<CacheProbe> measured;
    if (probe) measured = probe_caches(topo);
    // What a result's context would say about measuring here.
    const Instruments instruments = make_instruments("default", "auto", sysfs_root());
    const nlohmann::json context = build_context(topo, {}, instruments);
    if (json) {
        nlohmann::json j = to_json(topo);
        for (const char* key : {"instruments", "transparent_hugepages", "frequency_governor", "instruction_set"}) j[key] = context[key];
        if (measured) j["caches_measured"] = to_json(*measured, topo);
        std::cout << j.dump(2) << "\n";
        return 0;
    }
    std::cout << format_table(topo);
    if (measured) std::cout << "\n" << format_probe(*measured, topo);
    std::cout << "\nWhat can be measured here\n";
    auto state = [](const nlohmann::json& inst) {
        return inst["available"].get<bool>() ? std::string("available") : "not available (" + inst["reason"].get<std::string>() + ")";
    };
    for (const auto& [name, inst] : context["instruments"].items()) {
        std::cout << "  " << name << ": " << state(inst) << "\n";
        if (name == "perf_counters") {
            std::cout << "    hardware events: " << state(inst["hardware"]) << "\n    counted here by default:";
            for (const auto& e : inst["events"])
                if (e["available"].get<bool>()) std::cout << " " << e["name"].get<std::string>();
            std::cout << " (scope " << inst["scope"].get<std::string>() << ")\n";
        }
        if (name == "energy")
            for (const auto& d : inst["domains"]) std::cout << "    " << d["domain"].get<std::string>() << " " << d["source"].get<std::string>() << ": " << state(d) << "\n";
    }
    for (const char* key : {"transparent_hugepages", "frequency_governor"}) {
        const auto& v = context[key];
        std::cout << "  " << key << ": " << (v["value"].is_null() ? "unknown (" + v["reason"].get<std::string>() + ")" : v["value"].get<std::string>())
                  << "\n";
    }
    std::cout << "  built for: " << (context["instruction_set"]["avx512f"].get<bool>() ? "AVX-512" : context["instruction_set"]["avx2"].get<bool>() ? "AVX2" : "SSE2")
              << ", " << context["instruction_set"]["nt_store_bits"].get<int>() << "-bit streaming stores\n";
    return 0;
}

int cmd_run(const std::vector<std::string>& args, const std::vector<std::string>& full_argv) {
    CLI::App app{"suite: NUMA/cache micro-benchmarks with verified results"};
    app.footer(examples);
    app.get_formatter()->column_width(28);
    RunOptions opts;
    setup_run_options(app, opts);
    if (!parse(app, "suite", args)) return 0;
    const Topology topo = Topology::load();
    Plan plan = make_plan(opts, topo);
    if (opts.probe_caches && !plan.dry_run) {
        // The options are all checked before the seconds of probing; the plan is then made again
        // with the measured last level, which only changes the default sizes.
        if (!plan.quiet) std::cerr << "probing the caches (suite info --probe) ...\n";
        ProbeOptions po;
        po.hugepages = plan.settings.hugepages;
        const CacheProbe probe = probe_caches(topo, po);
        if (!plan.quiet) std::cerr << format_probe(probe, topo);
        opts.measured = measured_caches(probe, topo);
        plan = make_plan(opts, topo);
        plan.caches_measured = to_json(probe, topo);
    }
    return execute_plan(plan, topo, full_argv);
}

}  // namespace
}  // namespace suite

int main(int argc, char** argv) {
    using namespace suite;
    std::vector<std::string> all(argv, argv + argc);
    std::vector<std::string> args(all.begin() + 1, all.end());
    std::string command = "run";
    if (!args.empty() && !args[0].empty() && args[0][0] != '-') {
        command = args[0];
        args.erase(args.begin());
    }
    try {
        if (command == "run") return cmd_run(args, all);
        if (command == "list") return cmd_list(args);
        if (command == "info") return cmd_info(args);
        if (command == "compare") return cmd_compare(args);
        if (command == "check") return cmd_check(args);
        if (command == "deterministic") return cmd_deterministic(args, all);
        if (command == "traverse") return sfc::cmd_traverse(args);
        std::string hint = nearest(command, {"run", "list", "info", "compare", "check", "deterministic", "traverse"});
        throw UsageError("unknown command '" + command + "'" + (hint.empty() ? "" : " (did you mean '" + hint + "'?)") +
                         "; commands: run, list, info, compare, check, deterministic, traverse (see ./suite --help)");
    } catch (const CLI::ParseError& e) {
        if (e.get_exit_code() == 0) return 0;
        std::string msg = e.what();
        std::cerr << "suite: error: " << msg << " (see ./suite --help)\n";
        return 2;
    } catch (const UsageError& e) {
        std::cerr << "suite: error: " << e.what() << "\n";
        return 2;
    } catch (const std::exception& e) {
        std::cerr << "suite: error: " << e.what() << "\n";
        return 1;
    }
}
