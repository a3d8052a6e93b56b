#include "harness/measure/runner.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iterator>
#include <optional>
#include <stdexcept>

#include <unistd.h>

#include "harness/common/units.hpp"
#include "harness/instruments/callgrind_marks.hpp"

namespace suite {

namespace {

using Clock = std::chrono::steady_clock;  // CLOCK_MONOTONIC on Linux
static_assert(Clock::is_steady);

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

double clock_ticks_per_s() {
    const long t = sysconf(_SC_CLK_TCK);
    return t > 0 ? static_cast<double>(t) : 100.0;
}

void check_stop(const RunSettings& s) {
    if (s.stop && s.stop->load() != 0) throw Interrupted();
}

// In an MPI run, the point where every rank waits for the last one, and stops together if any
// of them was asked to stop (an allreduce is the barrier): a rank that left alone would leave
// the others waiting for it for ever. Without ranks, only this process's stop.
void sync_ranks(const RunSettings& s) {
    if (!s.comm) return check_stop(s);
    if (s.comm->max(s.stop && s.stop->load() != 0 ? 1 : 0) != 0) throw Interrupted();
}

// The most any rank wants of a count (the same on every rank); the count itself in one process.
int agree(const RunSettings& s, int mine) { return s.comm ? static_cast<int>(s.comm->max(mine)) : mine; }

}  // namespace

std::string callgrind_label(const Record& r) {
    return "suite point " + r.name + " " + r.access + " " + size_label(r.size_kind, r.size_requested) +
           " t=" + std::to_string(r.threads);
}

Rates derive_rates(const Work& work, const TimeStats& time, Metric metric, int threads) {
    Rates r;
    if (time.min <= 0) return r;
    r.units_per_second_best = work.units / time.min;
    if (work.flops > 0) r.gflops_best = work.flops / time.min / 1e9;
    if (metric == Metric::bandwidth) {
        // A kernel that moves no bytes it counts (peak-flops) has no bandwidth: not 0 GB/s.
        if (work.stream_bytes > 0) {
            r.stream_gbps_best = work.stream_bytes / time.min / 1e9;
            r.stream_gbps_median = work.stream_bytes / time.median / 1e9;
        }
        if (work.hardware_bytes > 0) {
            r.hardware_gbps_best = work.hardware_bytes / time.min / 1e9;
            r.hardware_gbps_median = work.hardware_bytes / time.median / 1e9;
        }
    } else {
        // Each thread chases units/threads loads one after another.
        const double loads_per_thread = work.units / threads;
        r.ns_per_load_best = time.min / loads_per_thread * 1e9;
        r.ns_per_load_median = time.median / loads_per_thread * 1e9;
    }
    return r;
}

Record run_point(const Point& point, const RunSettings& settings, const Topology& topo) {
    const KernelInfo& info = point.kernel->info;
    Record rec;
    rec.kernel = info.name;
    rec.variant = point.variant;
    rec.name = display_name(info.name, point.variant);
    rec.axis = info.axis;
    rec.access = point.access.label();
    rec.size_kind = info.size_kind;
    rec.size_requested = point.size;
    rec.size_role = point.role;
    rec.unit = info.unit;
    rec.metric = info.metric;
    rec.threads = point.threads;
    rec.pin = settings.pin.text;
    rec.placement = settings.placement.text;
    rec.seed = settings.seed;
    rec.mesh = point.mesh;

    rec.bindings = bind_team(topo, settings.pin, point.threads);
    std::vector<int> cpus;  // every CPU a thread of the team may run on
    for (const auto& b : rec.bindings) cpus.insert(cpus.end(), b.allowed.begin(), b.allowed.end());
    MemoryPolicy policy = resolve_policy(settings.placement, topo, cpus);
    policy.hugepages = settings.hugepages;
    rec.hugepages = hugepages_name(settings.hugepages);
    rec.placement_node = policy.node;
    rec.interleave_nodes = policy.nodes;

    KernelConfig cfg;
    cfg.access = point.access;
    cfg.variant = point.variant;
    cfg.size = point.size;
    cfg.seed = settings.seed;
    cfg.threads = point.threads;
    cfg.mesh = point.mesh;
    cfg.comm = settings.comm;
    // Every declared parameter, at its default where the point does not give it.
    cfg.params = default_params(info);
    for (const auto& [name, value] : point.params)
        if (cfg.params.count(name)) cfg.params[name] = value;
    rec.params = cfg.params;

    std::optional<Arena> arena(std::in_place, policy);
    auto kernel = point.kernel->make(cfg);
    kernel->setup(*arena);
    rec.pages = arena->observe();
    if (const std::uint64_t llc = topo.last_level_cache_total_bytes(); llc > 0 && !rec.pages.empty()) {
        std::uint64_t smallest = rec.pages.front().bytes;
        for (const auto& a : rec.pages) smallest = std::min(smallest, a.bytes);
        rec.smallest_array_over_llc = static_cast<double>(smallest) / static_cast<double>(llc);
    }
    rec.work = kernel->work();
    sync_ranks(settings);

    // Warm-up: not counted; it also tells how long one call takes.
    rec.warmup = 1;
    auto t0 = Clock::now();
    kernel->run(rec.warmup);
    double first = std::max(seconds_since(t0), 1e-9);
    // A call shorter than 50 samples is timed twice more, warm, and the fastest of the three
    // sizes the batch: the first runs on cold caches and TLBs, any may lose its CPU to another
    // process for a moment, and a batch sized from a slow one would be so small that the fixed
    // cost of a sample (the region's fork and join, the counter reads) weighs on every call.
    // In an MPI run the ranks decide together, so that each makes the same calls.
    for (int extra = 0; extra < 2 && agree(settings, first < 50 * settings.min_sample_s) != 0; ++extra) {
        t0 = Clock::now();
        kernel->run(1);
        first = std::max(std::min(first, seconds_since(t0)), 1e-9);
        ++rec.warmup;
    }
    rec.batch = first >= settings.min_sample_s ? 1 : static_cast<int>(std::ceil(settings.min_sample_s / first));
    rec.batch = agree(settings, rec.batch);
    // Those calls were timed a region each, fork and join included, which for a call of tens of
    // nanoseconds is most of the time (two threads at 32 KiB: 3.8 us a region, 60 ns a call): a
    // batch sized from them would fall far short of min_sample_s, and the fork and join would
    // weigh on every sample. One timed batch, warm, gives the time of a call within a batch.
    if (rec.batch > 1) {
        t0 = Clock::now();
        kernel->run(rec.batch);
        first = std::max(seconds_since(t0) / rec.batch, 1e-9);  // now a call's time within a batch
        rec.warmup += rec.batch;
        rec.batch = agree(settings, std::max(rec.batch, static_cast<int>(std::ceil(settings.min_sample_s / first))));
    }
    const double per_sample = first * rec.batch;
    rec.repetitions = settings.reps > 0 ? settings.reps
                                        : std::clamp(static_cast<int>(std::ceil(settings.min_time_s / per_sample)),
                                                     settings.min_reps, 1000000);
    rec.repetitions = agree(settings, rec.repetitions);

    // Counters are opened by the team's own threads; energy is read by this one. Both bracket
    // exactly the clock's interval, the counters innermost so that they see little but the kernel.
    Instruments* in = settings.instruments;
    TeamCounters counters;  // empty: counts nothing
    if (in && in->counters.requested) counters = TeamCounters(in->counters.events, point.threads, in->access);
    // An instrument that cannot measure here starts and stops as a no-op.
    EnergyInstrument& energy = in ? *in->energy : *energy_not_requested();  // the latter is static
    // Outermost first: started in this order, stopped in the reverse.
    RepetitionInstrument* const around[] = {&energy, &counters};

    rec.samples_s.reserve(static_cast<std::size_t>(rec.repetitions));
    // Not under valgrind: there the figures are callgrind's exact counts, not times; and the
    // snapshots and the reasons (strings whose length follows the timings) would leave a heap
    // that differs from run to run before the next counted calls, whose OpenMP region allocates:
    // the counts would no longer repeat exactly. The record then has no stability block.
    const bool judge_load = !callgrind::running_on_valgrind();
    const LoadSnapshot load_before = judge_load ? take_load_snapshot(cpus) : LoadSnapshot{};
    rec.fresh_arrays = settings.fresh_arrays;
    for (int r = 0; r < rec.repetitions; ++r) {
        if (r > 0 && settings.fresh_arrays) {
            // The old arrays go before the new ones come: one point's memory at a time. The new ones
            // follow the same policy; rec.pages stays the first set's.
            kernel.reset();
            arena.reset();
            arena.emplace(policy);
            kernel = point.kernel->make(cfg);
            kernel->setup(*arena);
            kernel->run(rec.batch);  // warm, as the first arrays were
            rec.warmup += rec.batch;
        }
        sync_ranks(settings);
        for (RepetitionInstrument* i : around) i->start();
        t0 = Clock::now();
        callgrind::toggle_collect();  // under `suite deterministic`, only the kernel's calls are counted
        kernel->run(rec.batch);
        callgrind::toggle_collect();
        const double seconds = seconds_since(t0);
        for (auto i = std::rbegin(around); i != std::rend(around); ++i) (*i)->stop(seconds);
        rec.samples_s.push_back(seconds / rec.batch);
    }
    const LoadSnapshot load_after = judge_load ? take_load_snapshot(cpus) : LoadSnapshot{};
    counters.check_team();
    callgrind::dump(callgrind_label(rec).c_str());
    rec.binding_held = team_still_bound(rec.bindings);
    rec.verification = kernel->verify();
    if (rec.verification.solver_failed)
        rec.verification.passed = false;  // a solver that did not converge verifies nothing
    rec.facts = kernel->facts();
    for (std::size_t i = 0; i < rec.facts.size(); ++i)
        for (std::size_t j = 0; j < i; ++j)
            if (rec.facts[i].name == rec.facts[j].name)
                throw std::logic_error("kernel " + info.name + " reported the fact '" + rec.facts[i].name + "' twice");
    rec.time = summarise(rec.samples_s);
    rec.rates = derive_rates(rec.work, rec.time, rec.metric, rec.threads);
    if (judge_load)
        rec.stability = assess_stability(load_before, load_after, rec.samples_s, rec.threads, settings.stability,
                                         clock_ticks_per_s());
    if (in) {
        rec.counters = counters.readings(rec.batch, rec.work.units, rec.work.stream_bytes, in->line_bytes);
        rec.counters.requested = in->counters.requested;
        rec.counters.omitted = in->counters.omitted;
        if (rec.counters.requested && in->counters.events.empty()) rec.counters.reason = "no event can be opened here";
        rec.energy = in->energy->take(rec.batch, rec.work.units, rec.work.stream_bytes, rec.time.median);
    }
    return rec;
}

}  // namespace suite
