// Google Benchmark's JSON format from a suite run (--format=gbench), as its own
// --benchmark_format=json writes it with --benchmark_repetitions: one "iteration" entry per
// repetition, then the aggregates. Counters are keys of each entry, as in Google Benchmark.
#include <cmath>

#include "harness/results/report.hpp"

namespace suite {

namespace {

using nlohmann::json;

std::string ctx_string(const json& c, const char* key) {
    auto it = c.find(key);
    return it != c.end() && it->is_string() ? it->get<std::string>() : std::string();
}

// hwloc's caches as Google Benchmark lists them: one entry per level and type.
json gbench_caches(const json& context) {
    json out = json::array();
    if (!context.contains("topology") || !context["topology"].contains("caches")) return out;
    for (const auto& c : context["topology"]["caches"]) {
        const std::string type = c.value("type", "");
        out.push_back({{"type", type == "data"          ? "Data"
                                : type == "instruction" ? "Instruction"
                                                        : "Unified"},
                       {"level", c.value("level", 0)},
                       {"size", c.value("size_bytes", std::uint64_t{0})},
                       {"num_sharing", c.value("pus_per_instance", 0)}});
    }
    return out;
}

// The rates of one time per call `t` (seconds), as Google Benchmark's counters.
void add_counters(json& entry, const Record& r, double t) {
    if (!(t > 0)) return;
    if (r.metric == Metric::bandwidth) {
        entry["bytes_per_second"] = r.work.stream_bytes / t;
        entry["hardware_bytes_per_second"] = r.work.hardware_bytes / t;
    } else {
        entry["ns_per_load"] = t / (r.work.units / r.threads) * 1e9;
    }
    entry["items_per_second"] = r.work.units / t;
    if (r.work.flops > 0) entry["flops_per_second"] = r.work.flops / t;
    entry["omp_threads"] = r.threads;
}

json base_entry(const std::string& name, std::size_t family, const Record& r) {
    return {{"name", name},
            {"family_index", family},
            {"per_family_instance_index", 0},
            {"run_name", name},
            {"repetitions", r.repetitions},
            {"threads", 1},  // Google Benchmark's threads; the OpenMP team is omp_threads
            {"time_unit", "ns"}};
}

}  // namespace

std::string gbench_name(const std::string& kernel_name, const std::string& access, const std::string& size,
                        int threads) {
    return kernel_name + "/" + access + "/" + size + "/" + std::to_string(threads) + "/real_time";
}

std::string render_gbench(const json& context, const std::vector<Record>& records, bool complete) {
    json ctx;
    ctx["date"] = ctx_string(context, "date");
    ctx["host_name"] = ctx_string(context, "host");
    const json argv = context.value("command_line", json::array());
    ctx["executable"] = argv.empty() || !argv[0].is_string() ? std::string("suite") : argv[0].get<std::string>();
    ctx["num_cpus"] = context.value("pus", 0);
    ctx["caches"] = gbench_caches(context);
    ctx["library_build_type"] = ctx_string(context, "build_type") == "Debug" ? "debug" : "release";
    // Custom context, as benchmark::AddCustomContext adds it: strings.
    ctx["suite_version"] = ctx_string(context, "suite_version");
    ctx["suite_git_revision"] = ctx_string(context, "git_revision");
    ctx["cpu_model"] = ctx_string(context, "cpu_model");
    ctx["compiler_flags"] = ctx_string(context, "compiler_flags");
    ctx["suite_complete"] = complete ? "true" : "false";
    ctx["suite_timing"] =
        "real_time: CLOCK_MONOTONIC around the whole OpenMP region, per kernel call; cpu_time is not measured by suite "
        "and repeats real_time; mhz_per_cpu is not known and left out";
    json benchmarks = json::array();
    for (std::size_t i = 0; i < records.size(); ++i) {
        const Record& r = records[i];
        const std::string name = gbench_name(r.name, r.access, size_label(r.size_kind, r.size_requested), r.threads);
        if (!r.verification.passed) {
            json e = base_entry(name, i, r);
            e.update({{"run_type", "iteration"},
                      {"repetition_index", 0},
                      {"iterations", 0},
                      {"real_time", 0},
                      {"cpu_time", 0},
                      {"error_occurred", true},
                      {"error_message", (r.verification.solver_failed ? "solver failed: " : "failed verification: ") +
                                            r.verification.detail}});
            benchmarks.push_back(e);
            continue;
        }
        for (std::size_t k = 0; k < r.samples_s.size(); ++k) {
            json e = base_entry(name, i, r);
            const double t = r.samples_s[k];
            e.update({{"run_type", "iteration"},
                      {"repetition_index", k},
                      {"iterations", r.batch},
                      {"real_time", t * 1e9},
                      {"cpu_time", t * 1e9}});
            add_counters(e, r, t);
            benchmarks.push_back(e);
        }
        // The aggregates Google Benchmark adds after repetitions: times in ns, cv as a fraction.
        const double stddev = r.time.cv * r.time.mean;
        const std::pair<const char*, double> aggregates[] = {
            {"mean", r.time.mean}, {"median", r.time.median}, {"stddev", stddev}, {"cv", r.time.cv}};
        for (const auto& [agg, value] : aggregates) {
            json e = base_entry(name + "_" + agg, i, r);
            e["run_name"] = name;
            const bool cv = std::string(agg) == "cv";
            const double v = cv ? value : value * 1e9;
            e.update({{"run_type", "aggregate"},
                      {"aggregate_name", agg},
                      {"aggregate_unit", cv ? "percentage" : "time"},
                      {"iterations", r.repetitions},
                      {"real_time", v},
                      {"cpu_time", v}});
            if (std::string(agg) == "mean" || std::string(agg) == "median") add_counters(e, r, value);
            benchmarks.push_back(e);
        }
    }
    return json{{"context", ctx}, {"benchmarks", benchmarks}}.dump(2) + "\n";
}

}  // namespace suite
