#include "harness/results/roofline_place.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "harness/common/units.hpp"
#include "harness/kernel/kernel.hpp"
#include "harness/machine/placement.hpp"
#include "harness/results/context_fields.hpp"
#include "harness/results/history.hpp"
#include "harness/results/result_file.hpp"

namespace suite {

namespace {

using nlohmann::json;

// Field access that names the file and the field in its error.
struct RoofReader {
    std::string path;
    [[noreturn]] void fail(const std::string& where, const std::string& what) const {
        throw InputError(path + ": " + where + ": " + what);
    }
    const json& field(const json& j, const char* name, const std::string& where) const {
        if (!j.is_object() || !j.contains(name)) fail(where.empty() ? name : where + "." + name, "missing");
        return j.at(name);
    }
    double number(const json& j, const char* name, const std::string& where) const {
        const json& v = field(j, name, where);
        if (!v.is_number() || !std::isfinite(v.get<double>()) || v.get<double>() < 0)
            fail(where + "." + name, "expected a number >= 0");
        return v.get<double>();
    }
    // A rate or count that no measurement gives as 0: a ceiling of 0 would place every point at
    // "0 % of nothing".
    double positive(const json& j, const char* name, const std::string& where) const {
        const double v = number(j, name, where);
        if (!(v > 0)) fail(where + "." + name, "is 0; expected a measured number > 0 (`suite roofline` writes them)");
        return v;
    }
    std::optional<double> optional_number(const json& j, const char* name, const std::string& where) const {
        if (!j.is_object() || !j.contains(name) || j.at(name).is_null()) return std::nullopt;
        return number(j, name, where);
    }
    std::string text(const json& j, const char* name, const std::string& where) const {
        const json& v = field(j, name, where);
        if (!v.is_string()) fail(where + "." + name, "expected a string");
        return v.get<std::string>();
    }
    const json& array(const json& j, const char* name, const std::string& where) const {
        const json& v = field(j, name, where);
        if (!v.is_array()) fail(where + "." + name, "expected an array");
        return v;
    }
};

std::optional<BandwidthFigure> read_roof_figure(const RoofReader& r, const json& j, const std::string& where) {
    if (j.is_null()) return std::nullopt;
    return BandwidthFigure{r.text(j, "kernel", where), r.positive(j, "gbps", where),
                           r.positive(j, "hardware_gbps", where)};
}

// A level that holds at least half of this footprint keeps part of it (see the header).
constexpr double level_reach = 2.0;

}  // namespace

RooflineFile parse_roofline_text(const std::string& text, const std::string& path) {
    RoofReader r{path};
    json doc;
    try {
        doc = json::parse(text);
    } catch (const json::parse_error& e) {
        throw InputError(path + ": not JSON (" + std::string(e.what()) + ")");
    }
    if (!doc.is_object() || !doc.contains("kind") || doc["kind"] != roofline_kind)
        throw InputError(path + ": not a roofline file (no \"kind\": \"" + roofline_kind +
                         "\"); write one with `suite roofline --out=FILE`");
    const json& version = r.field(doc, "schema_version", "");
    if (!version.is_number_integer() || version.get<int>() != roofline_schema_version)
        throw InputError(path + ": roofline schema_version " + version.dump() + ", but this suite reads version " +
                         std::to_string(roofline_schema_version) +
                         "; measure the ceilings again with this suite (`suite roofline`)");
    RooflineFile f;
    f.path = path;
    f.context = r.field(doc, "context", "");
    if (!f.context.is_object()) r.fail("context", "expected an object");
    f.fingerprint = machine_fingerprint(f.context);
    // The fingerprint written must be its context's: a file edited by hand (or another's context
    // pasted in) would otherwise place runs of one machine on another's ceilings.
    const json& written = r.field(doc, "fingerprint", "");
    if (!written.is_string() || written.get<std::string>() != f.fingerprint)
        r.fail("fingerprint", written.dump() + " is not its context's (" + f.fingerprint +
                                  "): the file was edited; measure the ceilings again (`suite roofline --out=FILE`)");
    Roofline& roof = f.roofline;
    const json& complete = r.field(doc, "complete", "");
    if (!complete.is_boolean()) r.fail("complete", "expected true or false");
    roof.complete = complete.get<bool>();
    // An interrupted measurement lacks thread counts or levels: nothing is placed on part of a roof.
    if (!roof.complete)
        throw InputError(path +
                         ": \"complete\": false, the measurement was interrupted; place on a complete one "
                         "(`suite roofline --out=FILE` run to its end)");
    const json& levels = r.array(doc, "levels", "");
    for (std::size_t i = 0; i < levels.size(); ++i) {
        const std::string at = "levels[" + std::to_string(i) + "]";
        RooflineLevel l;
        l.name = r.text(levels[i], "name", at);
        l.capacity_bytes = static_cast<std::uint64_t>(r.optional_number(levels[i], "capacity_bytes", at).value_or(0));
        l.instances = static_cast<int>(r.number(levels[i], "instances", at));
        l.pus_per_instance = static_cast<int>(r.number(levels[i], "pus_per_instance", at));
        l.source = r.text(levels[i], "source", at);
        roof.levels.push_back(l);
    }
    const json& ceilings = r.array(doc, "ceilings", "");
    if (ceilings.empty()) r.fail("ceilings", "empty: the file holds no measured ceiling");
    for (std::size_t i = 0; i < ceilings.size(); ++i) {
        const std::string at = "ceilings[" + std::to_string(i) + "]";
        ThreadCeilings tc;
        tc.threads = static_cast<int>(r.positive(ceilings[i], "threads", at));
        const json& peak = r.array(ceilings[i], "peak", at);
        for (std::size_t k = 0; k < peak.size(); ++k) {
            const std::string pat = at + ".peak[" + std::to_string(k) + "]";
            tc.peak.push_back(
                {r.text(peak[k], "isa", pat), r.text(peak[k], "kernel", pat), r.positive(peak[k], "gflops", pat)});
        }
        const json& bw = r.array(ceilings[i], "bandwidth", at);
        for (std::size_t k = 0; k < bw.size(); ++k) {
            const std::string bat = at + ".bandwidth[" + std::to_string(k) + "]";
            LevelCeiling lc;
            lc.level = r.text(bw[k], "level", bat);
            lc.footprint_bytes =
                static_cast<std::uint64_t>(r.optional_number(bw[k], "footprint_bytes", bat).value_or(0));
            lc.read_only = read_roof_figure(r, r.field(bw[k], "read_only", bat), bat + ".read_only");
            lc.read_write = read_roof_figure(r, r.field(bw[k], "read_write", bat), bat + ".read_write");
            const json& measured = r.array(bw[k], "measured", bat);
            for (std::size_t m = 0; m < measured.size(); ++m)
                if (auto fig = read_roof_figure(r, measured[m], bat + ".measured[" + std::to_string(m) + "]"))
                    lc.measured.push_back(*fig);
            if (bw[k].contains("reason") && bw[k]["reason"].is_string()) lc.reason = bw[k]["reason"].get<std::string>();
            tc.bandwidth.push_back(lc);
        }
        roof.ceilings.push_back(tc);
    }
    return f;
}

RooflineFile load_roofline_file(const std::string& path) {
    return parse_roofline_text(read_input_file(path, "a roofline file written by `suite roofline --out=FILE`"), path);
}

Placement place_points(const RooflineFile& roof, const ResultFile& file, const json& result) {
    const std::string& result_path = file.path;
    if (file.points.empty()) throw InputError(result_path + ": the result has no records to place");
    const std::string fp = machine_fingerprint(file.context);
    if (fp != roof.fingerprint)
        throw InputError(result_path + " was measured on " + file.machine_label() + ", the ceilings in " + roof.path +
                         " on " + context_text(roof.context, "host") + " (" + context_text(roof.context, "cpu_model") +
                         "): a point can only be placed on its own machine's ceilings; run `suite roofline` there");
    RoofReader r{result_path};
    Placement out;
    const json& records = result.at("results");
    for (std::size_t i = 0; i < records.size() && i < file.points.size(); ++i) {
        const json& rec = records[i];
        const LoadedPoint& lp = file.points[i];
        const std::string label = lp.key.label();
        const std::string at = "results[" + std::to_string(i) + "]";
        auto skip = [&](const std::string& why) { out.not_placed.push_back({label, why}); };
        if (lp.under_callgrind) {
            skip("measured under callgrind: its times are not the machine's");
            continue;
        }
        if (r.text(rec, "metric", at) != "bandwidth") {
            skip("a latency kernel: ns per dependent load, no rate to place");
            continue;
        }
        if (lp.mpi.scope != RankOrigin::Scope::none) {
            skip("a record of an MPI run: the ceilings are one process's");
            continue;
        }
        if (lp.key.placement != placement_name(PlacementKind::local)) {
            skip("placement " + lp.key.placement + ": the ceilings are measured with local memory");
            continue;
        }
        const json& work = r.field(rec, "work_per_repetition", at);
        const double flops = r.number(work, "flops", at + ".work_per_repetition");
        const double sbytes = r.number(work, "stream_bytes", at + ".work_per_repetition");
        const double hbytes = r.number(work, "hardware_bytes_estimate", at + ".work_per_repetition");
        const double tmin = r.number(r.field(rec, "time_s", at), "min", at + ".time_s");
        const ThreadCeilings* tc = nullptr;
        for (const auto& c : roof.roofline.ceilings)
            if (c.threads == lp.key.threads) tc = &c;
        if (!tc) {
            skip("no ceilings measured at " + std::to_string(lp.key.threads) +
                 " thread(s): `suite roofline --threads=" + std::to_string(lp.key.threads) + "`");
            continue;
        }
        if (tmin <= 0 || (sbytes <= 0 && flops <= 0)) {
            skip("no bytes and no flops declared: nothing to place");
            continue;
        }
        PlacedPoint p;
        p.label = label;
        p.kernel = lp.key.kernel;
        p.name = lp.key.variant.empty() ? p.kernel : p.kernel + "-" + lp.key.variant;
        if (const KernelEntry* k = find_kernel(p.kernel)) p.group = k->info.group;
        p.threads = lp.key.threads;
        p.footprint_bytes =
            static_cast<std::uint64_t>(r.number(r.field(rec, "size", at), "footprint_bytes", at + ".size"));
        p.verified = lp.verified;
        p.gbps = sbytes / tmin / 1e9;
        p.hardware_gbps = hbytes / tmin / 1e9;
        if (flops > 0) p.gflops = flops / tmin / 1e9;
        // Its level, and the ceiling measured there (or at the nearest faster level).
        const LevelCeiling* lc = nullptr;
        for (const auto& level : roof.roofline.levels) {
            const LevelCeiling* here = tc->level(level.name);
            if (here && !here->measured.empty()) lc = here;
            const std::uint64_t holds = level_bytes(level, p.threads);
            if (holds == 0 || static_cast<double>(p.footprint_bytes) <= level_reach * static_cast<double>(holds)) {
                p.level = level.name;
                break;
            }
        }
        const double peak = tc->peak_gflops();
        if (sbytes <= 0) {  // compute only (peak-flops): against the peak
            if (peak <= 0) {
                skip("no peak measured at this thread count");
                continue;
            }
            p.level = "registers", p.bound = "compute", p.ceiling_gflops = peak, p.fraction = *p.gflops / peak;
            out.points.push_back(p);
            continue;
        }
        if (!lc) {
            skip("no bandwidth ceiling measured at " + p.level + " or above for " + std::to_string(p.threads) +
                 " thread(s)");
            continue;
        }
        p.ceiling_gbps = lc->gbps();
        p.ceiling_hardware_gbps = lc->hardware_gbps();
        if (p.level != lc->level) p.level += " (ceiling of " + lc->level + ")";
        if (p.gflops && peak > 0) {
            p.intensity = flops / sbytes;
            const double roof_s = *p.intensity * p.ceiling_gbps;
            p.ceiling_gflops = std::min(peak, roof_s);
            p.bound = peak < roof_s ? "compute" : "bandwidth";
            p.fraction = *p.gflops / *p.ceiling_gflops;
            if (hbytes > 0 && p.ceiling_hardware_gbps > 0) {
                p.hardware_intensity = flops / hbytes;
                p.hardware_fraction = *p.gflops / std::min(peak, *p.hardware_intensity * p.ceiling_hardware_gbps);
            }
        } else {
            p.bound = "bandwidth";
            p.fraction = p.gbps / p.ceiling_gbps;
            if (hbytes > 0 && p.ceiling_hardware_gbps > 0)
                p.hardware_fraction = p.hardware_gbps / p.ceiling_hardware_gbps;
        }
        out.points.push_back(p);
    }
    return out;
}

json to_json(const Placement& pl, const std::string& roofline_path, const std::string& result_path) {
    auto opt = [](const std::optional<double>& v) { return v ? json(*v) : json(nullptr); };
    json points = json::array();
    for (const auto& p : pl.points)
        points.push_back({{"label", p.label},
                          {"name", p.name},
                          {"kernel", p.kernel},
                          {"group", p.group},
                          {"threads", p.threads},
                          {"footprint_bytes", p.footprint_bytes},
                          {"level", p.level},
                          {"verified", p.verified},
                          {"gflops", opt(p.gflops)},
                          {"gbps", p.gbps},
                          {"hardware_gbps", p.hardware_gbps},
                          {"intensity", {{"stream", opt(p.intensity)}, {"hardware", opt(p.hardware_intensity)}}},
                          {"ceiling",
                           {{"gflops", opt(p.ceiling_gflops)},
                            {"gbps", p.ceiling_gbps},
                            {"hardware_gbps", p.ceiling_hardware_gbps},
                            {"bound", p.bound}}},
                          {"fraction", p.fraction},
                          {"hardware_fraction", opt(p.hardware_fraction)}});
    json skipped = json::array();
    for (const auto& [label, why] : pl.not_placed) skipped.push_back({{"label", label}, {"reason", why}});
    return {{"kind", placement_kind},
            {"schema_version", roofline_schema_version},
            {"ceilings_file", roofline_path},
            {"result_file", result_path},
            {"points", points},
            {"not_placed", skipped}};
}

std::string render_placement(const Placement& pl) {
    std::string out;
    char buf[600];
    int width = 5;
    for (const auto& p : pl.points) width = std::max(width, static_cast<int>(p.label.size()));
    width = std::min(width, 200);
    std::snprintf(buf, sizeof buf, "%-*s %-22s %10s %9s %9s %10s %9s %7s\n", width, "point", "level", "GFLOP/s", "GB/s",
                  "flop/B", "ceiling", "fraction", "hw-frac");
    out += buf;
    for (const auto& p : pl.points) {
        const std::string ceiling = p.ceiling_gflops ? format_significant(*p.ceiling_gflops, 3) + " GF/s"
                                                     : format_significant(p.ceiling_gbps, 3) + " GB/s";
        std::snprintf(buf, sizeof buf, "%-*s %-22s %10s %9s %9s %10s %9.2f %7s%s\n", width, p.label.c_str(),
                      p.level.c_str(), p.gflops ? format_significant(*p.gflops, 3).c_str() : "-",
                      p.bound == "compute" && p.gbps == 0 ? "-" : format_significant(p.gbps, 3).c_str(),
                      p.intensity ? format_significant(*p.intensity, 3).c_str() : "-", ceiling.c_str(), p.fraction,
                      p.hardware_fraction ? format_significant(*p.hardware_fraction, 2).c_str() : "-",
                      p.verified ? "" : "  (FAILED verification)");
        out += buf;
    }
    if (!pl.not_placed.empty()) {
        out += "\nnot placed:\n";
        for (const auto& [label, why] : pl.not_placed) out += "  " + label + ": " + why + "\n";
    }
    return out;
}

std::string render_roofline(const Roofline& roof) {
    std::string out;
    char buf[300];
    for (const auto& tc : roof.ceilings) {
        out += "threads " + std::to_string(tc.threads) + ": peak ";
        for (const auto& p : tc.peak) out += p.isa + " " + format_significant(p.gflops, 4) + "  ";
        out += "GFLOP/s\n";
        std::snprintf(buf, sizeof buf, "  %-6s %10s %12s %14s %12s  %s\n", "level", "footprint", "GB/s", "kernel",
                      "ridge flop/B", "read-only / read-write GB/s");
        out += buf;
        for (const auto& lc : tc.bandwidth) {
            if (lc.measured.empty()) {
                out += "  " + lc.level + "  not measured: " + lc.reason + "\n";
                continue;
            }
            const std::string split =
                (lc.read_only ? format_significant(lc.read_only->gbps, 4) : std::string("-")) + " / " +
                (lc.read_write ? format_significant(lc.read_write->gbps, 4) + " (" + lc.read_write->kernel + ")"
                               : std::string("-"));
            std::snprintf(buf, sizeof buf, "  %-6s %10s %12s %14s %12s  %s\n", lc.level.c_str(),
                          format_bytes(lc.footprint_bytes).c_str(), format_significant(lc.gbps(), 4).c_str(),
                          lc.best_kernel().c_str(), format_significant(tc.peak_gflops() / lc.gbps(), 3).c_str(),
                          split.c_str());
            out += buf;
        }
    }
    return out;
}

}  // namespace suite
