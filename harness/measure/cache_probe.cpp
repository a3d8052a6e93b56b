#include "harness/measure/cache_probe.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "harness/common/units.hpp"
#include "harness/measure/runner.hpp"

namespace suite {

namespace {

// The footprints of the sweep: 4 KiB times 2^(k / points_per_octave), whole cache lines.
std::vector<std::uint64_t> sweep_sizes(std::uint64_t max_bytes, int per_octave) {
    std::vector<std::uint64_t> sizes;
    for (int k = 0;; ++k) {
        const double exact = 4096.0 * std::pow(2.0, static_cast<double>(k) / per_octave);
        const auto size = static_cast<std::uint64_t>(exact) / 64 * 64;
        if (size > max_bytes) break;
        if (sizes.empty() || size != sizes.back()) sizes.push_back(size);
    }
    return sizes;
}

std::uint64_t default_max_bytes(const Topology& topo) {
    return std::clamp<std::uint64_t>(4 * topo.last_level_cache_total_bytes(), 16ULL << 20, 512ULL << 20);
}

Record measure(const std::string& kernel, const std::string& pattern, std::uint64_t size, const RunSettings& settings,
               const Topology& topo) {
    const KernelEntry* k = find_kernel(kernel);
    if (!k) throw std::logic_error("the cache probe needs the '" + kernel + "' kernel (ProbeOptions names it)");
    Point p{k, Access{pattern, 0}, "", size, 1};
    k->validate(KernelConfig{p.access, "", size, settings.seed, 1});
    Record r = run_point(p, settings, topo);
    if (!r.verification.passed)
        throw std::runtime_error("the cache probe's " + kernel + " at " + format_bytes(size) +
                                 " failed verification: " + r.verification.detail);
    return r;
}

}  // namespace

CacheProbe probe_caches(const Topology& topo, const ProbeOptions& o) {
    const auto t0 = std::chrono::steady_clock::now();
    CacheProbe probe;
    RunSettings settings;
    // One thread on the first PU of the compact order (or unpinned on a topology that is not
    // this machine's); best of 3 repetitions, each at least a millisecond (the runner batches).
    settings.pin = parse_pin(pin_name(topo.this_system ? PinMode::compact : PinMode::none), topo);
    settings.placement.kind = PlacementKind::local;
    settings.placement.text = placement_name(PlacementKind::local);
    settings.hugepages = o.hugepages;
    settings.reps = 3;
    settings.stop = o.stop;
    probe.hugepages = hugepages_name(o.hugepages);

    const auto sizes = sweep_sizes(o.max_bytes ? o.max_bytes : default_max_bytes(topo), o.points_per_octave);
    const std::size_t memory_run = static_cast<std::size_t>(o.points_per_octave) * 3 / 2;  // one octave and a half
    std::size_t at_memory = 0;
    for (std::uint64_t size : sizes) {
        if (size < 128) continue;  // the chase needs two lines
        const Record r = measure(o.latency_kernel, o.latency_pattern, size, settings, topo);
        if (probe.cpu < 0 && !r.bindings.empty()) probe.cpu = r.bindings.front().requested_cpu;
        const double ns = r.rates.ns_per_load_best.value_or(0);
        probe.latency_ns.push_back({size, ns});
        at_memory = ns >= memory_latency_floor_ns ? at_memory + 1 : 0;
        if (at_memory >= memory_run) break;
    }
    probe.latency_steps = find_steps(probe.latency_ns, latency_step_options());
    probe.hierarchy = read_hierarchy(probe.latency_steps);

    if (o.bandwidth) {
        std::vector<CurvePoint> cost;  // ns per byte: rises level by level like the latency
        for (const auto& p : probe.latency_ns) {
            const Record r = measure(o.bandwidth_kernel, o.bandwidth_pattern, p.size_bytes, settings, topo);
            const double gbps = r.rates.stream_gbps_best.value_or(0);
            probe.bandwidth_gbps.push_back({p.size_bytes, gbps});
            if (gbps > 0) cost.push_back({p.size_bytes, 1.0 / gbps});
        }
        StepOptions so;
        so.min_step = 1.2;  // bandwidth steps are flatter than latency steps (prefetchers)
        so.jump = 1.15;
        so.tail_from_size = probe.hierarchy.memory_from;
        probe.bandwidth_steps = find_steps(cost, so).capacities;
    }
    probe.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return probe;
}

std::uint64_t measured_llc_total(const CacheProbe& probe, const Topology& topo) {
    const Hierarchy& h = probe.hierarchy;
    if (!h.memory_from || h.levels.empty() || !h.levels.back().capacity_bytes) return 0;
    const Cache* reported = topo.find_cache(h.levels.back().level);
    const auto instances = static_cast<std::uint64_t>(reported && reported->instances > 0 ? reported->instances : 1);
    return *h.levels.back().capacity_bytes * instances;
}

MeasuredCaches measured_caches(const CacheProbe& probe, const Topology& topo) {
    MeasuredCaches m;
    for (const auto& l : probe.hierarchy.levels) {
        if (l.partial || !l.capacity_bytes) continue;
        if (l.level == 1) m.l1 = *l.capacity_bytes;
        if (l.level == 2) m.l2 = *l.capacity_bytes;
    }
    m.llc_total = measured_llc_total(probe, topo);
    return m;
}

nlohmann::json to_json(const CacheProbe& probe, const Topology& topo) {
    using nlohmann::json;
    const Hierarchy& h = probe.hierarchy;
    json levels = json::array();
    for (const auto& l : h.levels) {
        const Cache* c = topo.find_cache(l.level);
        levels.push_back({{"level", l.level},
                          {"reported_bytes", c ? json(c->size_bytes) : json(nullptr)},
                          {"capacity_bytes", l.capacity_bytes ? json(*l.capacity_bytes) : json(nullptr)},
                          {"latency_ns", l.latency_ns},
                          {"partial", l.partial}});
    }
    json latency = json::array(), bandwidth = json::array();
    for (const auto& p : probe.latency_ns) latency.push_back({{"size_bytes", p.size_bytes}, {"ns", p.value}});
    for (const auto& p : probe.bandwidth_gbps) bandwidth.push_back({{"size_bytes", p.size_bytes}, {"gbps", p.value}});
    const std::uint64_t llc = measured_llc_total(probe, topo);
    return {
        {"method",
         "latency: the latency kernel (random pointer chase), 1 thread; bandwidth: the load kernel, 1 thread; "
         "footprints "
         "from 4 KiB in quarter-octave steps, best of 3 repetitions each; a level's capacity is where its latency has "
         "risen a fifth of the way (on a log scale) to the next level's; a plateau at 60 ns or more is memory; a "
         "partial "
         "level (no plateau) ends where a fifth of the extra latency of memory shows"},
        {"cpu", probe.cpu >= 0 ? json(probe.cpu) : json(nullptr)},
        {"hugepages", probe.hugepages},
        {"seconds", probe.seconds},
        {"levels", levels},
        {"memory_latency_ns", h.memory_latency_ns ? json(*h.memory_latency_ns) : json(nullptr)},
        {"memory_from_bytes", h.memory_from ? json(*h.memory_from) : json(nullptr)},
        {"last_level_total_bytes", llc ? json(llc) : json(nullptr)},
        {"bandwidth_steps_bytes", probe.bandwidth_steps},
        {"latency_sweep", latency},
        {"bandwidth_sweep", bandwidth}};
}

std::string format_probe(const CacheProbe& probe, const Topology& topo) {
    std::ostringstream o;
    const Hierarchy& h = probe.hierarchy;
    o << "Caches measured (pointer chase, 1 thread"
      << (probe.cpu >= 0 ? " on CPU " + std::to_string(probe.cpu) : std::string()) << ", " << probe.latency_ns.size()
      << " sizes from 4KiB to "
      << (probe.latency_ns.empty() ? std::string("-") : format_bytes(probe.latency_ns.back().size_bytes));
    char secs[32];
    std::snprintf(secs, sizeof secs, ", %.1f s)\n", probe.seconds);
    o << secs << "  level  reported (hwloc)  measured             latency\n";
    int deepest = 0;
    for (const auto& c : topo.caches)
        if (c.type != "instruction") deepest = std::max(deepest, c.level);
    for (const auto& l : h.levels) deepest = std::max(deepest, l.level);
    for (int level = 1; level <= deepest; ++level) {
        const Cache* c = topo.find_cache(level);
        const MeasuredLevel* m = nullptr;
        for (const auto& l : h.levels)
            if (l.level == level) m = &l;
        std::string measured = "not seen", latency = "-";
        if (m) {
            measured =
                m->capacity_bytes ? format_bytes(*m->capacity_bytes) + (m->partial ? " (partial)" : "") : "> sweep";
            char ns[32];
            std::snprintf(ns, sizeof ns, "%.2f ns", m->latency_ns);
            latency = ns;
        }
        char line[160];
        std::snprintf(line, sizeof line, "  L%-5d %-17s %-20s %s\n", level,
                      c ? format_bytes(c->size_bytes).c_str() : "-", measured.c_str(), latency.c_str());
        o << line;
    }
    if (h.memory_latency_ns) {
        char line[160];
        std::snprintf(line, sizeof line, "  memory %-17s from %-15s %.0f ns\n", "",
                      format_bytes(*h.memory_from).c_str(), *h.memory_latency_ns);
        o << line;
    } else {
        o << "  memory: not reached within the sweep\n";
    }
    if (!probe.bandwidth_gbps.empty()) {
        o << "  bandwidth (load, 1 thread) steps down at:";
        for (auto b : probe.bandwidth_steps) o << " " << format_bytes(b);
        if (probe.bandwidth_steps.empty()) o << " (no clear step)";
        o << "\n";
    }
    if (const std::uint64_t llc = measured_llc_total(probe, topo))
        o << "  last level measured, all instances: " << format_bytes(llc)
          << " (reported: " << format_bytes(topo.last_level_cache_total_bytes()) << ")\n";
    return o.str();
}

}  // namespace suite
