// suite-gbench: every registered kernel, in every pattern (or ordering) and variant it has, at
// each size and thread count, as a Google Benchmark benchmark named kernel/pattern/size/threads
// (Google Benchmark appends /real_time: the time is the wall clock of the whole OpenMP team).
// Users keep their Google Benchmark habits (--benchmark_filter, --benchmark_repetitions,
// --benchmark_format=json, its compare tooling); the names match `suite --format=gbench`.
//
// The kernels, pinning, placement and verification are the suite's own (harness/); Google
// Benchmark only decides the iterations and reports. One iteration is one kernel call, so at
// tiny sizes each iteration also pays for entering the OpenMP region (suite run batches calls).
#include <benchmark/benchmark.h>

#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "harness/common/units.hpp"
#include "harness/kernel/kernel.hpp"
#include "harness/machine/placement.hpp"
#include "harness/machine/team.hpp"
#include "harness/machine/topology.hpp"
#include "harness/measure/plan.hpp"
#include "harness/measure/result.hpp"
#include "harness/results/report.hpp"

namespace {

using namespace suite;

struct Options {
    std::string sizes;    // "" = the suite's default sizes for each thread count
    std::string threads;  // "" = 1 and all
    std::string pin = "compact";
};

const char* const usage =
    "suite-gbench: the suite's kernels as Google Benchmark benchmarks, named kernel/pattern/size/threads/real_time\n"
    "Options of its own (the rest are Google Benchmark's, e.g. --benchmark_filter, --benchmark_repetitions,\n"
    "--benchmark_format=json, --benchmark_min_time, --benchmark_list_tests):\n"
    "  --sizes=LIST     footprints: 32KiB,1MiB or a sweep 16KiB:1GiB (default: half an L1 and half an L2 per\n"
    "                   thread, and a DRAM size, as ./suite uses)\n"
    "  --threads=LIST   OpenMP thread counts: 1,2 | 1-8 | all (default: 1 and all)\n"
    "  --pin=MODE       compact | scatter | none | a CPU list (default: compact)\n"
    "Examples:\n"
    "  build/suite-gbench --benchmark_filter='add/random/.*' --benchmark_repetitions=5\n"
    "  build/suite-gbench --sizes=64MiB --threads=1 --benchmark_format=json --benchmark_out=gb.json\n";

// Takes the suite's own options out of argv (Google Benchmark rejects what it does not know).
Options take_options(int& argc, char** argv) {
    Options o;
    int kept = 1;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        auto value = [&](const char* flag) -> const char* {
            const std::size_t n = std::strlen(flag);
            return a.size() > n && a.compare(0, n, flag) == 0 && a[n] == '=' ? argv[i] + n + 1 : nullptr;
        };
        if (const char* v = value("--sizes"))
            o.sizes = v;
        else if (const char* v2 = value("--threads"))
            o.threads = v2;
        else if (const char* v3 = value("--pin"))
            o.pin = v3;
        else if (a == "--help" || a == "-h") {
            std::fputs(usage, stdout);
            std::exit(0);
        } else
            argv[kept++] = argv[i];
    }
    argc = kept;
    return o;
}

void run_kernel(benchmark::State& state, const KernelEntry* entry, KernelConfig cfg, const PinSpec& pin,
                const PlacementSpec& placement, const Topology& topo) {
    const auto bindings = bind_team(topo, pin, cfg.threads);
    std::vector<int> cpus;
    for (const auto& b : bindings) cpus.insert(cpus.end(), b.allowed.begin(), b.allowed.end());
    Arena arena(resolve_policy(placement, topo, cpus));
    auto kernel = entry->make(cfg);
    kernel->setup(arena);
    kernel->run(1);  // warm-up, as suite run does
    for (auto _ : state) kernel->run(1);
    const Verification v = kernel->verify();
    if (!v.passed || v.solver_failed) {
        state.SkipWithError(((v.solver_failed ? "solver failed: " : "failed verification: ") + v.detail).c_str());
        return;
    }
    const Work w = kernel->work();
    const auto calls = static_cast<double>(state.iterations());
    if (entry->info.metric == Metric::bandwidth) {
        state.SetBytesProcessed(static_cast<std::int64_t>(w.stream_bytes * calls));
        state.counters["hardware_bytes_per_second"] =
            benchmark::Counter(w.hardware_bytes * calls, benchmark::Counter::kIsRate);
    }
    state.SetItemsProcessed(static_cast<std::int64_t>(w.units * calls));
    state.counters["omp_threads"] = cfg.threads;
}

}  // namespace

int main(int argc, char** argv) {
    Options opts = take_options(argc, argv);
    try {
        static const Topology topo = Topology::load();
        static const PinSpec pin = parse_pin(opts.pin, topo);
        static const PlacementSpec placement = parse_placement("local", topo);
        const std::vector<int> threads = opts.threads.empty() ? std::vector<int>{1, topo.pu_count()}
                                                              : parse_thread_list(opts.threads, topo.pu_count());
        const std::vector<std::uint64_t> given =
            opts.sizes.empty() ? std::vector<std::uint64_t>{} : parse_size_list(opts.sizes);
        std::vector<std::string> seen;
        for (const auto& entry : kernels()) {
            const KernelInfo& info = entry.info;
            for (const auto& access_name : info.accesses) {
                // strided stands for strided:S; stride 8 (one double per 64 B line) represents it.
                const Access access{access_name, access_name == "strided" ? 8u : 0u};
                for (const auto& variant : info.variants)
                    for (int t : threads) {
                        if (t > 1 && single_thread_only(info, variant)) continue;
                        std::vector<std::uint64_t> sizes = given;
                        if (sizes.empty())
                            sizes = info.size_kind == SizeKind::bytes ? default_sizes(topo, t)
                                                                      : std::vector<std::uint64_t>{entry.test_size};
                        for (std::uint64_t size : sizes) {
                            KernelConfig cfg{access, variant, size, 1, t, "", default_params(info)};
                            try {
                                entry.validate(cfg);  // e.g. nt only with sequential, a size too small
                            } catch (const UsageError&) {
                                continue;
                            }
                            std::string name = gbench_name(display_name(info.name, variant), access.label(),
                                                           size_label(info.size_kind, size), t);
                            name.resize(name.size() - std::strlen("/real_time"));  // Google Benchmark adds it back
                            if (std::find(seen.begin(), seen.end(), name) != seen.end())
                                continue;  // e.g. two thread counts, same default size
                            seen.push_back(name);
                            const KernelEntry* e = &entry;
                            benchmark::RegisterBenchmark(
                                name.c_str(),
                                [e, cfg](benchmark::State& st) { run_kernel(st, e, cfg, pin, placement, topo); })
                                ->UseRealTime()
                                ->Unit(benchmark::kMicrosecond);
                        }
                    }
            }
        }
    } catch (const std::exception& e) {
        std::fprintf(stderr, "suite-gbench: error: %s\n", e.what());
        return 2;
    }
    benchmark::Initialize(&argc, argv);
    if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 2;
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    return 0;
}
