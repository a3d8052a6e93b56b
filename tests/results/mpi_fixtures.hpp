#pragma once
// Hand-made result documents of MPI runs (suite-mpi's format: results/schema/v1.json, the `mpi`
// of the context and of a record), built from real records of the committed fixtures: every
// point once per rank, each rank's times scaled by how slow that rank is, and the aggregate of
// all ranks (per repetition the slowest rank's time, the work of all ranks together).
#include <algorithm>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "tests/results/result_fixtures.hpp"

namespace suite::test {

struct MpiLayout {
    std::vector<std::pair<std::string, std::vector<int>>> hosts;  // each host and its ranks
    std::vector<double> slowness;                                 // per rank: its times over the template's
    int ranks() const { return static_cast<int>(slowness.size()); }
    std::string host_of(int rank) const {
        for (const auto& [host, ranks] : hosts)
            if (std::find(ranks.begin(), ranks.end(), rank) != ranks.end()) return host;
        return "?";
    }
};

// The record of `doc` for kernel/pattern/size/threads.
inline nlohmann::json template_record(const nlohmann::json& doc, const std::string& kernel, const std::string& pattern,
                                      std::uint64_t size, int threads) {
    for (const auto& r : doc["results"])
        if (r["kernel"] == kernel && r["pattern"] == pattern && r["size"]["requested"] == size &&
            r["threads"] == threads)
            return r;
    throw std::runtime_error("no such record in the fixture");
}

// `r` with every time `factor` times longer and `work` times the work: samples, statistics, rates.
inline nlohmann::json scaled(nlohmann::json r, double factor, double work = 1) {
    for (auto& s : r["time_s"]["samples"]) s = s.get<double>() * factor;
    for (const char* k : {"min", "median", "max", "mean"}) r["time_s"][k] = r["time_s"][k].get<double>() * factor;
    r["units_per_second_best"] = r["units_per_second_best"].get<double>() * work / factor;
    for (const char* k : {"units", "stream_bytes", "hardware_bytes_estimate", "flops"})
        r["work_per_repetition"][k] = r["work_per_repetition"][k].get<double>() * work;
    if (r["metric"] == "bandwidth") {
        for (const char* kind : {"stream", "hardware_estimate"})
            for (const char* k : {"best", "median"})
                r["bandwidth_gbps"][kind][k] = r["bandwidth_gbps"][kind][k].get<double>() * work / factor;
    } else {
        for (const char* k : {"best", "median"}) r["latency_ns"][k] = r["latency_ns"][k].get<double>() * factor;
    }
    return r;
}

// The document: `base`'s context as rank 0's with context.mpi, and for each template record its
// ranks' records and their aggregate.
inline nlohmann::json mpi_document(const nlohmann::json& base, const std::vector<nlohmann::json>& templates,
                                   const MpiLayout& layout) {
    using nlohmann::json;
    json doc = {{"schema_version", 1}, {"complete", true}, {"context", base["context"]}, {"results", json::array()}};
    json hosts = json::array();
    for (const auto& [host, ranks] : layout.hosts) {
        json cpus = json::array(), nodes = json::array();
        for (std::size_t i = 0; i < ranks.size(); ++i) {
            cpus.push_back(std::to_string(i));
            nodes.push_back(json::array({0}));
        }
        hosts.push_back({{"host", host},
                         {"ranks", ranks},
                         {"cpus", cpus},
                         {"numa_nodes", nodes},
                         {"disjoint", true},
                         {"cpu_model", base["context"]["cpu_model"]},
                         {"cores", 2},
                         {"pus", 2},
                         {"numa_node_count", 1},
                         {"memory_bytes", base["context"]["memory_bytes"]}});
    }
    doc["context"]["host"] = layout.hosts.front().first;
    doc["context"]["mpi"] = {{"library", "Open MPI v4.1.4 (hand-made fixture)"},
                             {"ranks", layout.ranks()},
                             {"layout", "split"},
                             {"hosts", hosts}};
    const auto slowest = std::max_element(layout.slowness.begin(), layout.slowness.end());
    const auto fastest = std::min_element(layout.slowness.begin(), layout.slowness.end());
    const int slowest_rank = static_cast<int>(slowest - layout.slowness.begin());
    for (const auto& t : templates) {
        for (int r = 0; r < layout.ranks(); ++r) {
            json rec = scaled(t, layout.slowness[r]);
            rec["mpi"] = {{"scope", "rank"}, {"rank", r}, {"ranks", layout.ranks()}, {"host", layout.host_of(r)}};
            doc["results"].push_back(rec);
        }
        // Every rank's samples are the template's scaled, so the slowest rank's are the longest
        // in every repetition (a latency, a time per load, is not summed: scaled() leaves it).
        json all = scaled(t, *slowest, layout.ranks());
        all["threads"] = t["threads"].get<int>() * layout.ranks();
        all["mpi"] = {{"scope", "aggregate"},
                      {"ranks", layout.ranks()},
                      {"hosts", layout.hosts.size()},
                      {"slowest_rank", slowest_rank},
                      {"slowest_host", layout.host_of(slowest_rank)},
                      {"spread", *slowest / *fastest}};
        doc["results"].push_back(all);
    }
    return doc;
}

// Two ranks on the one host "vm" of the committed fixtures; four ranks on two hosts.
inline MpiLayout two_ranks(double slow0, double slow1) { return {{{"vm", {0, 1}}}, {slow0, slow1}}; }
inline MpiLayout four_ranks_two_hosts(std::vector<double> slowness) {
    return {{{"node-a", {0, 1}}, {"node-b", {2, 3}}}, std::move(slowness)};
}

// The bandwidth records used: triad and add at 64 MiB on one thread (vm-native.json).
inline std::vector<nlohmann::json> bandwidth_templates() {
    const nlohmann::json plain = load(fixture("vm-native.json"));
    return {template_record(plain, "triad", "sequential", 64ULL << 20, 1),
            template_record(plain, "add", "random", 64ULL << 20, 1)};
}

}  // namespace suite::test
