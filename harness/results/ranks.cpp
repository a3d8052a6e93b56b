#include "harness/results/ranks.hpp"

#include <algorithm>
#include <stdexcept>

#include "harness/measure/runner.hpp"

namespace suite {

namespace {

const nlohmann::json& rank_field(const nlohmann::json& j, const char* name, const char* where) {
    if (!j.is_object() || !j.contains(name))
        throw std::runtime_error(std::string("a rank's record lacks ") + where + name);
    return j.at(name);
}

}  // namespace

RankRun rank_run_from_json(const nlohmann::json& record) {
    RankRun r;
    const nlohmann::json& mpi = rank_field(record, "mpi", "");
    r.rank = rank_field(mpi, "rank", "mpi.").get<int>();
    r.host = rank_field(mpi, "host", "mpi.").get<std::string>();
    r.threads = rank_field(record, "threads", "").get<int>();
    r.samples_s = rank_field(rank_field(record, "time_s", ""), "samples", "time_s.").get<std::vector<double>>();
    const nlohmann::json& w = rank_field(record, "work_per_repetition", "");
    r.work.units = rank_field(w, "units", "work_per_repetition.").get<double>();
    r.work.stream_bytes = rank_field(w, "stream_bytes", "work_per_repetition.").get<double>();
    r.work.hardware_bytes = rank_field(w, "hardware_bytes_estimate", "work_per_repetition.").get<double>();
    r.work.flops = rank_field(w, "flops", "work_per_repetition.").get<double>();
    r.work.footprint_bytes =
        rank_field(rank_field(record, "size", ""), "footprint_bytes", "size.").get<std::uint64_t>();
    const nlohmann::json& v = rank_field(record, "verification", "");
    r.passed = rank_field(v, "passed", "verification.").get<bool>();
    r.detail = rank_field(v, "detail", "verification.").get<std::string>();
    // null: not measured (a solver that did not converge); 0 here takes nothing from the others.
    const nlohmann::json& err = rank_field(v, "max_error", "verification.");
    r.max_error = err.is_null() ? 0.0 : err.get<double>();
    r.solver_failed = v.value("solver_failed", false);
    const nlohmann::json& pin = rank_field(record, "pin", "");
    r.held = rank_field(pin, "held_during_run", "pin.").get<bool>();
    auto known = [](const nlohmann::json& v) { return v.is_number_integer() ? v.get<int>() : -1; };
    for (const auto& t : rank_field(pin, "threads", "pin.")) {
        ThreadBinding b;
        b.thread = rank_field(t, "thread", "pin.threads[].").get<int>();
        b.allowed = rank_field(t, "allowed_cpus", "pin.threads[].").get<std::vector<int>>();
        b.requested_cpu = known(rank_field(t, "requested_cpu", "pin.threads[]."));
        b.cpu = known(rank_field(t, "cpu", "pin.threads[]."));
        b.numa_node = known(rank_field(t, "numa_node", "pin.threads[]."));
        r.bindings.push_back(std::move(b));
    }
    if (record.contains("stability")) {
        r.unstable = record["stability"].value("unstable", false);
        for (const auto& why : record["stability"].value("reasons", nlohmann::json::array()))
            if (why.is_string()) r.unstable_why += (r.unstable_why.empty() ? "" : "; ") + why.get<std::string>();
    }
    return r;
}

Record aggregate_record(const Record& first, const std::vector<RankRun>& ranks, int hosts) {
    if (ranks.empty()) throw std::logic_error("aggregate_record: no ranks");
    Record a = first;
    a.threads = 0;
    a.work = Work{};
    a.binding_held = true;
    a.verification = Verification{};
    a.verification.passed = true;
    std::string failures;
    const std::size_t reps = ranks.front().samples_s.size();
    a.samples_s.assign(reps, 0.0);
    double best_fastest = 0, best_slowest = -1;
    const RankRun* slowest = nullptr;
    for (const RankRun& r : ranks) {
        if (r.samples_s.size() != reps)
            throw std::logic_error("rank " + std::to_string(r.rank) + " timed " + std::to_string(r.samples_s.size()) +
                                   " repetitions, rank " + std::to_string(ranks.front().rank) + " " +
                                   std::to_string(reps));
        a.threads += r.threads;
        a.work.units += r.work.units;
        a.work.stream_bytes += r.work.stream_bytes;
        a.work.hardware_bytes += r.work.hardware_bytes;
        a.work.flops += r.work.flops;
        a.work.footprint_bytes += r.work.footprint_bytes;
        a.binding_held = a.binding_held && r.held;
        for (std::size_t i = 0; i < reps; ++i) a.samples_s[i] = std::max(a.samples_s[i], r.samples_s[i]);
        const double best = reps ? *std::min_element(r.samples_s.begin(), r.samples_s.end()) : 0;
        if (best > best_slowest) best_slowest = best, slowest = &r;
        if (&r == &ranks.front() || best < best_fastest) best_fastest = best;
        a.verification.max_error = std::max(a.verification.max_error, r.max_error);
        a.verification.solver_failed = a.verification.solver_failed || r.solver_failed;
        if (!r.passed) {
            a.verification.passed = false;
            if (failures.empty()) failures = "rank " + std::to_string(r.rank) + " (" + r.host + "): " + r.detail;
        }
        if (r.unstable && r.rank != first.mpi.rank) {
            a.stability.unstable = true;
            a.stability.reasons.push_back(
                {"another rank", "rank " + std::to_string(r.rank) + " was unstable: " + r.unstable_why});
        }
    }
    a.verification.detail = a.verification.passed
                                ? "every one of the " + std::to_string(ranks.size()) + " ranks verified its share"
                                : failures;
    a.time = summarise(a.samples_s);
    a.rates = derive_rates(a.work, a.time, a.metric, a.threads);
    a.bindings.clear();
    for (const RankRun& r : ranks)
        for (ThreadBinding b : r.bindings) {
            b.thread = static_cast<int>(a.bindings.size());
            a.bindings.push_back(std::move(b));
        }
    a.pages.clear();
    a.counters = CounterReadings{};
    a.counters.requested = first.counters.requested;
    a.counters.scope = first.counters.scope.empty() ? "user+kernel" : first.counters.scope;
    a.counters.reason = "counters are in each rank's record; a sum over ranks is not taken";
    a.energy = EnergyReadings{};
    a.energy.requested = first.energy.requested;
    a.energy.reason =
        "energy is in each rank's record: the ranks of one host share its packages, so a sum would count them twice";
    a.facts = first.facts;
    a.mpi = RankScope{};
    a.mpi.kind = RankScope::Kind::aggregate;
    a.mpi.ranks = static_cast<int>(ranks.size());
    a.mpi.hosts = hosts;
    a.mpi.slowest_rank = slowest->rank;
    a.mpi.slowest_host = slowest->host;
    a.mpi.spread = best_fastest > 0 ? best_slowest / best_fastest : 1.0;
    return a;
}

}  // namespace suite
