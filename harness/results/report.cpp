#include "harness/results/report.hpp"

#include <cmath>
#include <map>
#include <sstream>

#include "harness/common/units.hpp"
#include "harness/measure/instrument_set.hpp"
#include "harness/results/result_file.hpp"

namespace suite {

namespace {

nlohmann::json opt(const std::optional<double>& v) { return v ? nlohmann::json(*v) : nlohmann::json(nullptr); }

const char* axis_name(AccessAxis a) { return a == AccessAxis::pattern ? "pattern" : "ordering"; }

// What was asked of huge pages, and how much of the arrays they backed after first touch (the
// sum over the arrays; null with the reason when an array's share could not be read).
nlohmann::json hugepages_json(const Record& r) {
    nlohmann::json j = {{"requested", r.hugepages}};
    std::uint64_t total = 0;
    for (const auto& a : r.pages) {
        if (!a.anon_huge_bytes) {
            j["anon_huge_bytes"] = nullptr;
            j["reason"] = "array '" + a.name + "': " + (a.huge_error.empty() ? std::string("not read") : a.huge_error);
            return j;
        }
        total += *a.anon_huge_bytes;
    }
    j["anon_huge_bytes"] = total;
    return j;
}

std::string fmt(const char* f, double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, f, v);
    return buf;
}

std::string csv_opt(const std::optional<double>& v) { return v ? fmt("%.6g", *v) : ""; }

// A fact's value; null where it is not a finite number (JSON has no NaN), e.g. an eigenvalue
// of a solver that did not converge.
nlohmann::json finite_or_null(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }

}  // namespace

namespace {

nlohmann::json reason_texts(const Stability& s) {
    nlohmann::json texts = nlohmann::json::array();
    for (const auto& r : s.reasons) texts.push_back(r.text);
    return texts;
}

}  // namespace

nlohmann::json to_json(const Stability& s) {
    return {{"unstable", s.unstable},
            {"reasons", reason_texts(s)},
            {"spread", s.spread},
            {"steal_fraction", opt(s.steal_fraction)},
            {"others_fraction", opt(s.others_fraction)},
            {"waited_fraction", opt(s.waited_fraction)},
            {"involuntary_switches", s.involuntary_switches},
            {"window_s", s.window_s},
            {"load_average_1m", opt(s.load_average)}};
}

nlohmann::json to_json(const Record& r) {
    nlohmann::json j;
    j["kernel"] = r.kernel;
    j["variant"] = r.variant;
    j["name"] = r.name;
    j["axis"] = axis_name(r.axis);
    j[axis_name(r.axis)] = r.access;
    j["unit"] = r.unit;
    j["metric"] = r.metric == Metric::bandwidth ? "bandwidth" : "latency";
    j["size"] = {{"kind", r.size_kind == SizeKind::bytes ? "bytes" : "count"},
                 {"requested", r.size_requested},
                 {"footprint_bytes", r.work.footprint_bytes},
                 {"smallest_array_over_llc", opt(r.smallest_array_over_llc)},
                 {"units", r.work.units}};
    if (!r.size_role.name.empty())
        j["size"]["role"] = {{"name", r.size_role.name},
                             {"cache", r.size_role.cache},
                             {"cache_bytes", r.size_role.cache_bytes},
                             {"source", r.size_role.source}};
    j["threads"] = r.threads;
    nlohmann::json bindings = nlohmann::json::array();
    for (const auto& b : r.bindings) bindings.push_back(to_json(b));
    j["pin"] = {{"requested", r.pin}, {"threads", bindings}, {"held_during_run", r.binding_held}};
    nlohmann::json pages = nlohmann::json::array();
    for (const auto& a : r.pages) pages.push_back(to_json(a));
    j["placement"] = {{"requested", r.placement},
                      {"node", r.placement_node >= 0 ? nlohmann::json(r.placement_node) : nlohmann::json(nullptr)},
                      {"interleave_nodes", r.interleave_nodes},
                      {"arrays", pages}};
    j["hugepages"] = hugepages_json(r);
    j["repetitions"] = {
        {"counted", r.repetitions}, {"warmup", r.warmup}, {"batch", r.batch}, {"fresh_arrays", r.fresh_arrays}};
    j["time_s"] = {{"min", r.time.min},   {"median", r.time.median}, {"max", r.time.max},
                   {"mean", r.time.mean}, {"cv", r.time.cv},         {"samples", r.samples_s}};
    j["work_per_repetition"] = {{"units", r.work.units},
                                {"stream_bytes", r.work.stream_bytes},
                                {"hardware_bytes_estimate", r.work.hardware_bytes},
                                {"flops", r.work.flops}};
    if (r.metric == Metric::bandwidth)
        j["bandwidth_gbps"] = {
            {"stream", {{"best", opt(r.rates.stream_gbps_best)}, {"median", opt(r.rates.stream_gbps_median)}}},
            {"hardware_estimate",
             {{"best", opt(r.rates.hardware_gbps_best)}, {"median", opt(r.rates.hardware_gbps_median)}}}};
    if (r.metric == Metric::bandwidth && r.work.stream_bytes <= 0)
        j["bandwidth_gbps"]["reason"] = "the kernel moves no bytes it counts (its work is flops): no bandwidth";
    else if (r.metric != Metric::bandwidth)
        j["bandwidth_gbps"] = nullptr;
    if (r.metric == Metric::latency)
        j["latency_ns"] = {{"best", opt(r.rates.ns_per_load_best)}, {"median", opt(r.rates.ns_per_load_median)}};
    else
        j["latency_ns"] = nullptr;
    j["units_per_second_best"] = r.rates.units_per_second_best;
    j["gflops_best"] = opt(r.rates.gflops_best);
    j["counters"] = to_json(r.counters);
    j["energy"] = to_json(r.energy);
    if (r.stability.assessed) j["stability"] = to_json(r.stability);  // absent: not judged (under valgrind)
    j["verification"] = {
        {"passed", r.verification.passed}, {"detail", r.verification.detail}, {"max_error", r.verification.max_error}};
    if (r.verification.solver_failed) {
        j["verification"]["solver_failed"] = true;
        // No converged answer was compared with the expected one: the error is not 0, it is unknown.
        j["verification"]["max_error"] = nullptr;
        j["verification"]["max_error_reason"] = "the solver did not converge: no answer was compared";
    }
    j["seed"] = r.seed;
    if (!r.mesh.empty()) j["mesh"] = r.mesh;
    if (!r.params.empty()) j["parameters"] = params_json(r.params);
    if (!r.facts.empty()) {
        nlohmann::json facts = nlohmann::json::object();
        for (const auto& f : r.facts) facts[f.name] = {{"value", finite_or_null(f.value)}, {"unit", f.unit}};
        j["facts"] = facts;
    }
    if (r.mpi.kind == RankScope::Kind::rank)
        j["mpi"] = {{"scope", "rank"}, {"rank", r.mpi.rank}, {"ranks", r.mpi.ranks}, {"host", r.mpi.host}};
    else if (r.mpi.kind == RankScope::Kind::aggregate)
        j["mpi"] = {{"scope", "aggregate"},
                    {"ranks", r.mpi.ranks},
                    {"hosts", r.mpi.hosts},
                    {"slowest_rank", r.mpi.slowest_rank},
                    {"slowest_host", r.mpi.slowest_host},
                    {"spread", r.mpi.spread}};
    return j;
}

namespace {

// Counter and energy columns, named after the first record's events and domains (every record
// of a run has the same ones, in the same order); a cell is empty where nothing was measured.
std::string domain_label(const DomainEnergy& d) { return d.domain + (d.socket ? std::to_string(*d.socket) : ""); }

}  // namespace

std::string params_text(const Params& params) {
    std::string out;
    for (const auto& [name, value] : params) out += (out.empty() ? "" : ";") + name + "=" + param_text(value);
    return out;
}

std::string csv_header(const Record* first) {
    std::string h =
        "kernel,variant,name,axis,access,size_requested,footprint_bytes,units,stream_bytes,hardware_bytes_estimate,"
        "flops,"
        "threads,pin,placement,repetitions,batch,time_min_s,time_median_s,time_max_s,time_mean_s,time_cv,"
        "stream_gbps_best,stream_gbps_median,hardware_gbps_best,hardware_gbps_median,ns_per_load_best,ns_per_load_"
        "median,"
        "gflops_best,units_per_second_best,verified,parameters,unstable,hugepages,host,cpu_model,date,"
        "git_revision";
    if (first) {
        for (const auto& e : first->counters.events) h += ",counter_" + e.name + "_per_call";
        for (const auto& d : first->energy.domains) h += ",energy_" + domain_label(d) + "_j_per_call";
    }
    return h + "\n";
}

std::string to_csv_row(const Record& r, const nlohmann::json& context) {
    // The run's identity on every row, so that CSVs of several machines or runs concatenated
    // (or loaded into one table) can still be told apart.
    auto ctx = [&](const char* key) {
        const auto it = context.is_object() ? context.find(key) : context.end();
        std::string v = it != context.end() && it->is_string() ? it->get<std::string>() : "";
        for (char& c : v)
            if (c == '"') c = '\'';
        return "\"" + v + "\"";
    };
    std::ostringstream o;
    o << r.kernel << ',' << r.variant << ',' << r.name << ',' << axis_name(r.axis) << ',' << r.access << ','
      << r.size_requested << ',' << r.work.footprint_bytes << ',' << fmt("%.0f", r.work.units) << ','
      << fmt("%.17g", r.work.stream_bytes) << ',' << fmt("%.17g", r.work.hardware_bytes) << ','
      << fmt("%.17g", r.work.flops) << ',' << r.threads << ",\"" << r.pin << "\"," << r.placement << ','
      << r.repetitions << ',' << r.batch << ',' << fmt("%.9g", r.time.min) << ',' << fmt("%.9g", r.time.median) << ','
      << fmt("%.9g", r.time.max) << ',' << fmt("%.9g", r.time.mean) << ',' << fmt("%.4g", r.time.cv) << ','
      << csv_opt(r.rates.stream_gbps_best) << ',' << csv_opt(r.rates.stream_gbps_median) << ','
      << csv_opt(r.rates.hardware_gbps_best) << ',' << csv_opt(r.rates.hardware_gbps_median) << ','
      << csv_opt(r.rates.ns_per_load_best) << ',' << csv_opt(r.rates.ns_per_load_median) << ','
      << csv_opt(r.rates.gflops_best) << ',' << fmt("%.6g", r.rates.units_per_second_best) << ','
      << (r.verification.passed ? "true" : "false") << ',' << params_text(r.params) << ','
      << (r.stability.unstable ? "true" : "false") << ',' << r.hugepages << ',' << ctx("host") << ','
      << ctx("cpu_model") << ',' << ctx("date") << ',' << ctx("git_revision");
    for (const auto& e : r.counters.events) o << ',' << (e.available ? fmt("%.9g", e.per_call.median) : "");
    for (const auto& d : r.energy.domains) o << ',' << (d.available ? fmt("%.9g", d.joules_per_call.median) : "");
    o << '\n';
    return o.str();
}

std::string stability_summary(const std::vector<Record>& records) {
    std::size_t unstable = 0;
    std::map<std::string, std::size_t> kinds;  // how many points passed each threshold
    for (const auto& r : records) {
        if (!r.stability.unstable) continue;
        ++unstable;
        for (const auto& why : r.stability.reasons) ++kinds[why.kind];
    }
    if (unstable == 0) return "";
    std::string out =
        std::to_string(unstable) + " of " + std::to_string(records.size()) +
        " point(s) unstable (the machine was busy or the repetitions spread; `suite check` calls them inconclusive):";
    std::string sep = " ";
    for (const auto& [kind, n] : kinds) {
        out += sep + kind + " (" + std::to_string(n) + ")";
        sep = ", ";
    }
    return out + "\n";
}

std::string table_header() {
    char buf[256];
    std::snprintf(buf, sizeof buf, "%-7s %-10s %-12s %9s %3s %-10s %10s %10s %10s %6s %6s %s\n", "#", "kernel",
                  "pattern", "size", "thr", "placement", "best", "median", "hw-est", "cv%", "reps", "check");
    return std::string(buf) + std::string(110, '-') + "\n";
}

std::string table_row(std::size_t index, std::size_t total, const Record& r) {
    std::string best = "-", median = "-", hw = "-";
    if (r.work.stream_bytes == 0 && r.rates.gflops_best) {  // no memory traffic (peak-flops): its rate is its flops
        best = fmt("%.2f GF/s", *r.rates.gflops_best);
        median = fmt("%.2f", r.work.flops / r.time.median / 1e9);
    } else if (r.metric == Metric::bandwidth && r.rates.stream_gbps_best) {
        best = fmt("%.2f GB/s", *r.rates.stream_gbps_best);
        median = fmt("%.2f", *r.rates.stream_gbps_median);
        hw = fmt("%.2f", *r.rates.hardware_gbps_best);
    } else if (r.metric == Metric::latency && r.rates.ns_per_load_best) {
        best = fmt("%.2f ns", *r.rates.ns_per_load_best);
        median = fmt("%.2f", *r.rates.ns_per_load_median);
    }
    const std::string size = size_label(r.size_kind, r.size_requested);
    std::string pos = std::to_string(index) + "/" + std::to_string(total);
    char buf[320];
    std::snprintf(buf, sizeof buf, "%-7s %-10s %-12s %9s %3d %-10s %10s %10s %10s %6.1f %6d %s\n", pos.c_str(),
                  r.name.c_str(), r.access.c_str(), size.c_str(), r.threads, r.placement.c_str(), best.c_str(),
                  median.c_str(), hw.c_str(), r.time.cv * 100.0, r.repetitions,
                  r.verification.passed ? (r.stability.unstable ? "ok unstable" : "ok")
                                        : (r.stability.unstable ? "FAILED unstable" : "FAILED"));
    std::string row = buf;
    // What the kernel reported about the run, on a line of its own under the row.
    if (!r.facts.empty()) {
        std::string line;
        for (const auto& f : r.facts)
            line +=
                (line.empty() ? "" : ", ") + f.name + "=" + fmt("%.6g", f.value) + (f.unit.empty() ? "" : " " + f.unit);
        row += "        " + line + "\n";
    }
    return row;
}

std::string ResultDocument::render(FileFormat format, bool complete) const {
    if (format == FileFormat::csv) {
        std::string out = csv_header(records.empty() ? nullptr : &records.front());
        for (const auto& r : records) out += to_csv_row(r, context);
        return out;
    }
    if (format == FileFormat::gbench) return render_gbench(context, records, complete);
    nlohmann::json doc;
    doc["schema_version"] = schema_version;
    doc["complete"] = complete;
    doc["context"] = context;
    doc["results"] = nlohmann::json::array();
    for (const auto& r : records) doc["results"].push_back(to_json(r));
    return doc.dump(1) + "\n";
}

}  // namespace suite
