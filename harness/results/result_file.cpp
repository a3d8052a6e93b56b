#include "harness/results/result_file.hpp"

#include <sys/stat.h>
#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <set>
#include <sstream>

#include "harness/common/input_file.hpp"
#include "harness/common/stats.hpp"
#include "harness/kernel/kernel.hpp"
#include "harness/results/context_fields.hpp"
#include "harness/results/result_fields.hpp"

namespace suite {

namespace {

using nlohmann::json;

// The deepest nesting of [ and { outside strings: a hostile file of a million '[' must be
// refused before a recursive reader goes near it.
std::size_t nesting_depth(const std::string& text) {
    std::size_t depth = 0, deepest = 0;
    bool in_string = false, escaped = false;
    for (char c : text) {
        if (in_string) {
            if (escaped)
                escaped = false;
            else if (c == '\\')
                escaped = true;
            else if (c == '"')
                in_string = false;
        } else if (c == '"') {
            in_string = true;
        } else if (c == '[' || c == '{') {
            deepest = std::max(deepest, ++depth);
        } else if ((c == ']' || c == '}') && depth > 0) {
            --depth;
        }
    }
    return deepest;
}

// Spread estimated from a min..max range of a few dozen repetitions (about four standard deviations).
double range_spread(const FieldReader& r, const json& stats, const std::string& where) {
    const double median = r.number(stats, "median", where), lo = r.number(stats, "min", where),
                 hi = r.number(stats, "max", where);
    // A spread from figures out of order would be negative and shrink the gate's threshold.
    if (!(lo <= median && median <= hi)) r.fail(where, "expected min <= median <= max");
    return median > 0 ? (hi - lo) / (4 * median) : 0.0;
}

void read_counters(const FieldReader& r, const json& block, const std::string& where, LoadedPoint& p) {
    if (!r.boolean(block, "available", where)) return;
    const json& events = r.field(block, "events", where);
    if (!events.is_array()) r.fail(where + ".events", "expected an array");
    for (std::size_t e = 0; e < events.size(); ++e) {
        const std::string at = where + ".events[" + std::to_string(e) + "]";
        const std::string name = r.string(events[e], "name", at);
        if (!r.boolean(events[e], "available", at)) continue;
        const json& per_element = r.field(events[e], "per_element", at);
        if (per_element.is_null()) continue;
        Measure m{"counter " + name,
                  "per element",
                  Direction::lower_is_better,
                  0,
                  r.number(per_element, at + ".per_element"),
                  0,
                  {},
                  NAN};
        m.best = m.median;
        const json& per_call = r.field(events[e], "per_call", at);
        if (!per_call.is_null()) {
            m.noise = range_spread(r, per_call, at + ".per_call");
            const double med = r.number(per_call, "median", at + ".per_call");
            m.count_per_call = med;
            if (med > 0) m.best = m.median * r.number(per_call, "min", at + ".per_call") / med;
        }
        p.measures.push_back(m);
    }
}

void read_energy(const FieldReader& r, const json& block, const std::string& where, LoadedPoint& p) {
    if (!r.boolean(block, "available", where)) return;
    const json& domains = r.field(block, "domains", where);
    if (!domains.is_array()) r.fail(where + ".domains", "expected an array");
    for (std::size_t d = 0; d < domains.size(); ++d) {
        const std::string at = where + ".domains[" + std::to_string(d) + "]";
        std::string name = r.string(domains[d], "domain", at);
        const json& socket = r.field(domains[d], "socket", at);
        if (socket.is_number_integer())
            name.append("-").append(std::to_string(socket.get<std::int64_t>()));
        else if (!socket.is_null())
            r.fail(at + ".socket", "expected an integer or null");
        const json& j = r.field(domains[d], "joules_per_call", at);
        const std::string jat = at + ".joules_per_call";
        Measure m{"energy " + name,
                  "J/call",
                  Direction::lower_is_better,
                  r.number(j, "min", jat),
                  r.number(j, "median", jat),
                  range_spread(r, j, jat),
                  {},
                  NAN};
        p.measures.push_back(m);
    }
}

// Counts of a run under valgrind's callgrind (suite deterministic): exact, so no noise.
void read_callgrind(const FieldReader& r, const json& block, const std::string& where, LoadedPoint& p) {
    const json& per_call = r.field(block, "per_call", where);
    const std::string at = where + ".per_call";
    auto add = [&](const char* name, double v) {
        Measure m{name, "per call", Direction::lower_is_better, v, v, 0, {}, NAN};
        m.count_per_call = v;
        p.measures.push_back(m);
    };
    add("callgrind instructions", r.number(per_call, "Ir", at));
    add("callgrind D1 misses", r.number(per_call, "D1mr", at) + r.number(per_call, "D1mw", at));
    add("callgrind LL misses", r.number(per_call, "DLmr", at) + r.number(per_call, "DLmw", at));
}

// Whether parameter `name` of `kernel` may hold a name: a named parameter of a kernel this build
// has, or any parameter of a kernel it lacks (another build's); a number parameter never.
bool may_be_named(const std::string& kernel, const std::string& name) {
    const KernelEntry* k = find_kernel(kernel);
    if (!k) return true;
    for (const auto& p : k->info.params)
        if (p.name == name) return !p.choices.empty();
    return true;
}

LoadedPoint read_point(const FieldReader& r, const json& rec, std::size_t index, const std::optional<LoadedMpiJob>& job,
                       int version) {
    const std::string where = "results[" + std::to_string(index) + "]";
    if (!rec.is_object()) r.fail(where, "expected an object");
    LoadedPoint p;
    PointKey& k = p.key;
    k.kernel = r.string(rec, "kernel", where);
    k.variant = r.string(rec, "variant", where, true);
    const std::string axis = r.string(rec, "axis", where);
    if (axis != "pattern" && axis != "ordering") r.fail(where + ".axis", "expected 'pattern' or 'ordering'");
    k.access = r.string(rec, axis.c_str(), where);
    const json& size = r.field(rec, "size", where);
    k.size_kind = r.string(size, "kind", where + ".size");
    k.size = r.count(size, "requested", where + ".size", 1);
    if (auto it = size.find("role"); it != size.end()) {
        const std::string at = where + ".size.role";
        if (!it->is_object()) r.fail(at, "expected an object");
        p.role.name = r.string(*it, "name", at);
        p.role.cache = r.string(*it, "cache", at, true);
        p.role.cache_bytes = r.count(*it, "cache_bytes", at, 0);
    }
    k.threads = static_cast<int>(std::min<std::uint64_t>(r.count(rec, "threads", where, 1), 1u << 30));
    k.pin = r.string(r.field(rec, "pin", where), "requested", where + ".pin");
    k.placement = r.string(r.field(rec, "placement", where), "requested", where + ".placement");
    p.verified = r.boolean(r.field(rec, "verification", where), "passed", where + ".verification");
    // The kernel's parameters (absent in older files, and for kernels without any) tell points
    // apart as the size does: any finite number, negative ones included, or a named parameter's name.
    if (auto it = rec.find("parameters"); it != rec.end()) {
        if (!it->is_object()) r.fail(where + ".parameters", "expected an object of numbers and names");
        for (const auto& [name, value] : it->items()) {
            if (value.is_string() && version >= 2 && may_be_named(k.kernel, name)) {
                k.params[name] = value.get<std::string>();
                continue;
            }
            if (!value.is_number() || !std::isfinite(value.get<double>()))
                r.fail(where + ".parameters." + name,
                       version >= 2 ? "expected a finite number or a name" : "expected a finite number");
            k.params[name] =
                version >= 2 ? ParamValue(value.get<double>()) : v1_param(k.kernel, name, value.get<double>());
        }
    }
    p.mpi = read_rank_origin(r, rec, where, job);
    if (p.mpi.scope != RankOrigin::Scope::none)
        k.rank_scope = rank_scope_text(p.mpi.scope == RankOrigin::Scope::rank ? p.mpi.rank : -1, p.mpi.ranks);

    if (rec.contains("callgrind")) {
        p.under_callgrind = true;
        read_callgrind(r, rec["callgrind"], where + ".callgrind", p);
    } else {
        const std::string metric = r.string(rec, "metric", where);
        if (metric != "bandwidth" && metric != "latency")
            r.fail(where + ".metric", "expected 'bandwidth' or 'latency'");
        const json& time = r.field(rec, "time_s", where);
        const json& samples = r.field(time, "samples", where + ".time_s");
        if (!samples.is_array() || samples.empty()) r.fail(where + ".time_s.samples", "expected a non-empty array");
        std::vector<double> s;
        for (std::size_t i = 0; i < samples.size(); ++i)
            s.push_back(r.number(samples[i], where + ".time_s.samples[" + std::to_string(i) + "]"));
        const double noise = robust_relative_spread(s);
        const bool bw = metric == "bandwidth";
        const std::string at = bw ? where + ".bandwidth_gbps" : where + ".latency_ns";
        const json& rates =
            bw ? r.field(r.field(rec, "bandwidth_gbps", where), "stream", at) : r.field(rec, "latency_ns", where);
        const std::string rat = bw ? at + ".stream" : at;
        const json& best = r.field(rates, "best", rat);
        const json& median = r.field(rates, "median", rat);
        // A kernel that moves no bytes but counts flops (peak-flops): its headline is GFLOP/s.
        const json* work = rec.contains("work_per_repetition") ? &rec["work_per_repetition"] : nullptr;
        const bool flops_only =
            bw && work && work->is_object() && work->value("stream_bytes", 1.0) == 0 && work->value("flops", 0.0) > 0;
        const double min_time = r.number(r.field(time, "min", where + ".time_s"), where + ".time_s.min");
        // null: the rate could not be derived (a best time of 0); the point then has no headline.
        if (flops_only && min_time > 0) {
            const double flops = work->value("flops", 0.0);
            Measure m{"flops",
                      "GFLOP/s",
                      Direction::higher_is_better,
                      flops / min_time / 1e9,
                      flops / median_of(s) / 1e9,
                      noise,
                      {},
                      NAN};
            for (double t : s)
                if (t > 0) m.samples.push_back(flops / t / 1e9);
            p.measures.push_back(m);
        } else if (!best.is_null() && !median.is_null()) {
            Measure m{bw ? "bandwidth" : "latency",
                      bw ? "GB/s" : "ns/load",
                      bw ? Direction::higher_is_better : Direction::lower_is_better,
                      r.number(best, rat + ".best"),
                      r.number(median, rat + ".median"),
                      noise,
                      {},
                      NAN};
            // Each repetition's figure: the rate goes as 1/time and the latency as time, scaled
            // so that the median time gives the recorded median.
            const double median_time = median_of(s);
            if (median_time > 0)
                for (double t : s)
                    if (t > 0) m.samples.push_back(bw ? m.median * median_time / t : m.median * t / median_time);
            p.measures.push_back(m);
        }
    }
    if (auto it = rec.find("hugepages"); it != rec.end() && it->is_object())
        p.hugepages = r.string(*it, "requested", where + ".hugepages");
    // The noise flag; optional, absent in older files.
    if (auto it = rec.find("stability"); it != rec.end() && !it->is_null()) {
        const std::string at = where + ".stability";
        p.unstable = r.boolean(*it, "unstable", at);
        if (p.unstable) {
            const json& reasons = r.field(*it, "reasons", at);
            if (!reasons.is_array()) r.fail(at + ".reasons", "expected an array of strings");
            for (std::size_t i = 0; i < reasons.size(); ++i) {
                if (!reasons[i].is_string()) r.fail(at + ".reasons[" + std::to_string(i) + "]", "expected a string");
                p.unstable_why += (p.unstable_why.empty() ? "" : "; ") + reasons[i].get<std::string>();
            }
        }
    }
    // Issue 3's instruments; optional, absent in older files.
    if (rec.contains("counters") && !rec["counters"].is_null())
        read_counters(r, rec["counters"], where + ".counters", p);
    if (rec.contains("energy") && !rec["energy"].is_null()) read_energy(r, rec["energy"], where + ".energy", p);
    return p;
}

}  // namespace

std::string PointKey::size_label() const { return size_kind == "bytes" ? format_bytes(size) : std::to_string(size); }

ParamValue v1_param(const std::string& kernel, const std::string& name, double value) {
    const KernelEntry* k = find_kernel(kernel);
    if (!k) return value;
    for (const auto& p : k->info.params)
        if (p.name == name && !p.v1_order.empty() && value >= 0 && value == std::floor(value) &&
            value < static_cast<double>(p.v1_order.size()))
            return p.v1_order[static_cast<std::size_t>(value)];
    return value;
}

json params_json(const Params& params) {
    json out = json::object();
    for (const auto& [name, value] : params)
        out[name] = std::holds_alternative<std::string>(value) ? json(std::get<std::string>(value))
                                                               : json(std::get<double>(value));
    return out;
}

Params params_from_json(const json& j, const std::string& kernel) {
    Params out;
    for (const auto& [name, value] : j.items())
        out[name] =
            value.is_string() ? ParamValue(value.get<std::string>()) : v1_param(kernel, name, value.get<double>());
    return out;
}

std::string PointKey::label() const { return label_with_threads("t=" + std::to_string(threads)); }

std::string PointKey::label_with_threads(const std::string& threads_text) const {
    std::string out = (variant.empty() ? kernel : kernel + "-" + variant) + " " + access + " " + size_label() + " " +
                      threads_text + " " + pin + "/" + placement;
    for (const auto& [name, value] : params) out += " " + name + "=" + param_text(value);
    if (!rank_scope.empty()) out += " " + rank_scope;
    return out;
}

std::string ResultFile::machine_label() const {
    const std::string host = context_text(context, "host"), cpu = context_text(context, "cpu_model");
    return host + " (" + (cpu.empty() ? "unknown CPU" : cpu) + ")";
}

ResultFile parse_result_text(const std::string& text, const std::string& path) {
    FieldReader r{path};
    if (nesting_depth(text) > 256)
        throw InputError(path + ": not a suite result file (JSON nested more than 256 levels deep)");
    json doc;
    try {
        doc = json::parse(text);
    } catch (const json::exception& e) {
        std::string why = e.what();
        if (auto close = why.find("] "); why.rfind("[json.exception", 0) == 0 && close != std::string::npos)
            why = why.substr(close + 2);
        throw InputError(path + ": not valid JSON (truncated or not a result file?): " + why);
    }
    if (!doc.is_object())
        throw InputError(path +
                         ": not a suite result file (the JSON is not an object with schema_version, context, results)");
    if (doc.contains("benchmarks") && !doc.contains("results"))
        throw InputError(
            path +
            ": not a suite result file (it looks like Google Benchmark output: 'benchmarks', no 'results'); "
            "compare suite's own JSON (--out=FILE.json)");
    if (!doc.contains("schema_version"))
        throw InputError(
            path + ": not a suite result file (no schema_version; suite writes schema_version, context and results)");
    const json& version = doc["schema_version"];
    if (!version.is_number_integer()) r.fail("schema_version", "expected an integer");
    const std::int64_t v = version.get<std::int64_t>();
    if (v < oldest_readable_schema_version || v > readable_schema_version)
        throw InputError(path + ": schema_version " + std::to_string(v) + " is not one this suite reads (it reads " +
                         std::to_string(oldest_readable_schema_version) + " to " +
                         std::to_string(readable_schema_version) + "); use the suite version that wrote it");
    ResultFile f;
    f.path = path;
    f.schema_version = static_cast<int>(v);
    f.complete = r.boolean(doc, "complete", "$");
    f.context = r.field(doc, "context", "$");
    if (!f.context.is_object()) r.fail("context", "expected an object");
    f.mpi = read_mpi_job(r, f.context);
    const json& results = r.field(doc, "results", "$");
    if (!results.is_array()) r.fail("results", "expected an array");
    std::set<PointKey> seen;
    for (std::size_t i = 0; i < results.size(); ++i) {
        LoadedPoint p = read_point(r, results[i], i, f.mpi, f.schema_version);
        if (!seen.insert(p.key).second) {
            f.notes.push_back(path + ": results[" + std::to_string(i) + "] repeats " + p.key.label() +
                              "; the first one is used");
            continue;
        }
        f.points.push_back(std::move(p));
    }
    return f;
}

std::string read_input_file(const std::string& path, const std::string& example) {
    const InputText in = read_regular_file(path, 1ULL << 30);
    if (!in.ok) throw InputError(path + ": " + in.reason + "; give " + example);
    if (in.text.empty()) throw InputError(path + ": the file is empty; give " + example);
    return in.text;
}

ResultFile load_result_file(const std::string& path) {
    const std::string text =
        read_input_file(path, "a result file written by suite --out=FILE.json (e.g. results/latest.json)");
    return parse_result_text(text, path);
}

}  // namespace suite
