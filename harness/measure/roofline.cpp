#include "harness/measure/roofline.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "harness/common/units.hpp"
#include "harness/measure/default_sizes.hpp"
#include "harness/measure/runner.hpp"

namespace suite {

namespace {

void keep_best(std::optional<BandwidthFigure>& best, const BandwidthFigure& f) {
    if (!best || f.gbps > best->gbps) best = f;
}

}  // namespace

std::uint64_t level_bytes(const RooflineLevel& level, int threads) {
    if (level.capacity_bytes == 0) return 0;
    const int per = std::max(level.pus_per_instance, 1);
    const int used = std::clamp((threads + per - 1) / per, 1, std::max(level.instances, 1));
    return level.capacity_bytes * static_cast<std::uint64_t>(used);
}

double LevelCeiling::gbps() const {
    double best = 0;
    for (const auto& f : measured) best = std::max(best, f.gbps);
    return best;
}

double LevelCeiling::hardware_gbps() const {
    double best = 0;
    for (const auto& f : measured) best = std::max(best, f.hardware_gbps);
    return best;
}

std::string LevelCeiling::best_kernel() const {
    const BandwidthFigure* best = nullptr;
    for (const auto& f : measured)
        if (!best || f.gbps > best->gbps) best = &f;
    return best ? best->kernel : "";
}

double ThreadCeilings::peak_gflops() const {
    double best = 0;
    for (const auto& p : peak) best = std::max(best, p.gflops);
    return best;
}

const LevelCeiling* ThreadCeilings::level(const std::string& name) const {
    for (const auto& l : bandwidth)
        if (l.level == name) return &l;
    return nullptr;
}

std::vector<RooflineLevel> roofline_levels(const Topology& topo, const CacheProbe* probe) {
    std::vector<RooflineLevel> out;
    for (int lv = 1; lv <= 4; ++lv) {
        const Cache* c = topo.find_cache(lv);
        RooflineLevel l;
        l.name = "L" + std::to_string(lv);
        l.instances = c ? std::max(c->instances, 1) : 1;
        l.pus_per_instance = c ? std::max(c->pus_per_instance, 1) : 1;
        if (probe) {
            // The probe's level of this number, when it found a capacity (a level the sweep
            // ended on has none). A VM reports caches it does not give; the probe is believed.
            for (const auto& m : probe->hierarchy.levels)
                if (m.level == lv && m.capacity_bytes) l.capacity_bytes = *m.capacity_bytes, l.source = "measured";
            if (l.capacity_bytes == 0 && !probe->hierarchy.levels.empty() &&
                lv > static_cast<int>(probe->hierarchy.levels.size()))
                continue;
        }
        if (l.capacity_bytes == 0 && c && c->size_bytes) l.capacity_bytes = c->size_bytes, l.source = "reported";
        if (l.capacity_bytes == 0) continue;
        out.push_back(l);
    }
    out.push_back({"DRAM", 0, 1, 1, "memory"});
    return out;
}

Roofline measure_roofline(const Topology& topo, const RooflineOptions& o) {
    const auto t0 = std::chrono::steady_clock::now();
    Roofline roof;
    MeasuredCaches measured;
    std::optional<CacheProbe> probe;
    if (o.probe) {
        ProbeOptions po = o.probe_options;
        po.stop = o.stop;
        try {
            probe = probe_caches(topo, po);
            roof.caches_measured = to_json(*probe, topo);
            measured = measured_caches(*probe, topo);
        } catch (const Interrupted&) {
            roof.complete = false;
        }
    }
    roof.levels = roofline_levels(topo, probe ? &*probe : nullptr);
    if (!roof.complete) return roof;

    RunSettings settings;
    settings.pin = o.pin;
    settings.placement.kind = PlacementKind::local;
    settings.placement.text = placement_name(PlacementKind::local);
    settings.min_time_s = o.min_time_s;
    settings.stop = o.stop;
    auto stopped = [&] { return o.stop && o.stop->load() != 0; };
    auto say = [&](const std::string& line) {
        if (o.progress) o.progress(line);
    };
    // One verified point; nullopt when the kernel refuses the configuration (why: `refused`).
    auto measure = [&](const std::string& name, const std::string& variant, std::uint64_t size, int threads,
                       std::string& refused) -> std::optional<Record> {
        const KernelEntry* k = find_kernel(name);
        if (!k) throw std::logic_error("the roofline needs the '" + name + "' kernel (RooflineOptions names it)");
        // A variant this build lacks (the x86 string instructions on aarch64) is no ceiling here.
        if (!variant.empty() && !std::ranges::count(k->info.variants, variant)) {
            refused = "kernel '" + name + "' has no variant '" + variant + "' in this build";
            return std::nullopt;
        }
        Point p{k, Access{k->info.accesses.front(), 0}, variant, size, threads};
        try {
            k->validate(KernelConfig{p.access, variant, size, settings.seed, threads});
        } catch (const UsageError& e) {
            refused = e.what();
            return std::nullopt;
        }
        Record r = run_point(p, settings, topo);
        if (!r.verification.passed)
            throw std::runtime_error("the roofline's " + r.name + " at " + size_label(k->info.size_kind, size) +
                                     " on " + std::to_string(threads) +
                                     " thread(s) failed verification: " + r.verification.detail);
        return r;
    };

    // The thread count being measured: kept as far as it got when a signal stops the work.
    ThreadCeilings tc;
    try {
        for (int t : o.threads) {
            tc = ThreadCeilings{};
            tc.threads = t;
            const KernelEntry* peak = find_kernel(o.peak_kernel);
            if (!peak)
                throw std::logic_error("the roofline needs the '" + o.peak_kernel + "' kernel (RooflineOptions)");
            // The widths this CPU runs (an SVE build's sve is a variant, but not on a CPU without SVE).
            for (const auto& isa :
                 peak->info.default_variants.empty() ? peak->info.variants : peak->info.default_variants) {
                std::string refused;
                const auto r = measure(o.peak_kernel, isa, peak->info.default_count, t, refused);
                if (!r) throw std::logic_error(o.peak_kernel + " refused its own default size: " + refused);
                tc.peak.push_back({isa, r->name, r->rates.gflops_best.value_or(0)});
                say("peak  " + r->name + " on " + std::to_string(t) +
                    " thread(s): " + format_significant(tc.peak.back().gflops, 4) + " GFLOP/s");
            }
            const std::uint64_t dram = o.dram_bytes ? o.dram_bytes : default_sizes(topo, t, measured).back();
            std::uint64_t below = 0;  // what the level below holds for these threads
            for (const auto& level : roof.levels) {
                LevelCeiling lc;
                lc.level = level.name;
                const bool memory = level.capacity_bytes == 0;
                const std::uint64_t holds = level_bytes(level, t);
                const std::uint64_t footprint = memory ? dram : holds / 2 / 4096 * 4096;
                if (!memory && footprint <= below) {
                    lc.reason = "half of " + level.name + " for " + std::to_string(t) + " thread(s) (" +
                                format_bytes(holds / 2) + ") fits in the levels above";
                } else {
                    lc.footprint_bytes = footprint;
                    for (const auto& ck : o.ceiling_kernels) {
                        if (ck.memory_only && !memory) continue;
                        std::string refused;
                        const auto r = measure(ck.kernel, ck.variant, footprint, t, refused);
                        if (!r) continue;  // too small for this kernel at this thread count
                        const BandwidthFigure f{r->name, r->rates.stream_gbps_best.value_or(0),
                                                r->rates.hardware_gbps_best.value_or(0)};
                        lc.measured.push_back(f);
                        keep_best(ck.read_only ? lc.read_only : lc.read_write, f);
                        say(level.name + "  " + r->name + " " + format_bytes(footprint) + " on " + std::to_string(t) +
                            " thread(s): " + format_significant(f.gbps, 4) + " GB/s");
                    }
                    if (lc.measured.empty())
                        lc.reason = "no ceiling kernel runs at " + format_bytes(footprint) + " on " +
                                    std::to_string(t) + " thread(s)";
                }
                if (!memory) below = std::max(below, holds);
                tc.bandwidth.push_back(lc);
            }
            roof.ceilings.push_back(std::move(tc));
            tc = ThreadCeilings{};
        }
    } catch (const Interrupted&) {
        roof.complete = false;
        // What was measured of the interrupted thread count stays, each level it did not reach
        // saying so (not a ceiling of 0).
        if (!tc.peak.empty()) {
            for (std::size_t i = tc.bandwidth.size(); i < roof.levels.size(); ++i) {
                LevelCeiling lc;
                lc.level = roof.levels[i].name;
                lc.reason = "not measured: interrupted";
                tc.bandwidth.push_back(lc);
            }
            roof.ceilings.push_back(std::move(tc));
        }
    }
    if (stopped()) roof.complete = false;
    roof.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return roof;
}

nlohmann::json to_json(const Roofline& roof) {
    using nlohmann::json;
    json levels = json::array();
    for (const auto& l : roof.levels)
        levels.push_back({{"name", l.name},
                          {"capacity_bytes", l.capacity_bytes ? json(l.capacity_bytes) : json(nullptr)},
                          {"instances", l.instances},
                          {"pus_per_instance", l.pus_per_instance},
                          {"source", l.source}});
    auto figure = [](const std::optional<BandwidthFigure>& f) -> json {
        if (!f) return nullptr;
        return {{"kernel", f->kernel}, {"gbps", f->gbps}, {"hardware_gbps", f->hardware_gbps}};
    };
    json ceilings = json::array();
    for (const auto& tc : roof.ceilings) {
        json peak = json::array();
        for (const auto& p : tc.peak) peak.push_back({{"isa", p.isa}, {"kernel", p.kernel}, {"gflops", p.gflops}});
        json bw = json::array();
        for (const auto& lc : tc.bandwidth) {
            json measured = json::array();
            for (const auto& f : lc.measured) measured.push_back(figure(f));
            json entry = {{"level", lc.level},
                          {"footprint_bytes", lc.footprint_bytes ? json(lc.footprint_bytes) : json(nullptr)},
                          {"gbps", lc.measured.empty() ? json(nullptr) : json(lc.gbps())},
                          {"hardware_gbps", lc.measured.empty() ? json(nullptr) : json(lc.hardware_gbps())},
                          {"kernel", lc.measured.empty() ? json(nullptr) : json(lc.best_kernel())},
                          {"read_only", figure(lc.read_only)},
                          {"read_write", figure(lc.read_write)},
                          {"measured", measured}};
            if (!lc.reason.empty()) entry["reason"] = lc.reason;
            bw.push_back(entry);
        }
        ceilings.push_back({{"threads", tc.threads},
                            {"peak_gflops", tc.peak.empty() ? json(nullptr) : json(tc.peak_gflops())},
                            {"peak", peak},
                            {"bandwidth", bw}});
    }
    return {{"complete", roof.complete},
            {"seconds", roof.seconds},
            {"levels", levels},
            {"ceilings", ceilings},
            {"caches_measured", roof.caches_measured}};
}

}  // namespace suite
