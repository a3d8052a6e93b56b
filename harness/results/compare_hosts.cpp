#include "harness/results/compare_hosts.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <set>

#include "harness/results/compare_figures.hpp"
#include "harness/results/context_fields.hpp"
#include "harness/results/text_table.hpp"

namespace suite {

namespace {

// One column of the view: a host and its ranks, or on a single host one rank.
struct Lane {
    std::string name;  // "node1", "rank 0"
    std::vector<int> ranks;
};

// The rank records of one point, and its aggregate record where the file has it.
struct RankGroup {
    PointKey key;  // the first rank's, without its rank scope
    std::map<int, const LoadedPoint*> by_rank;
    const LoadedPoint* aggregate = nullptr;
};

// The rank records grouped by point, in the order of the file. A rank's threads are not part of
// the point (ranks given uneven shares of a host run different counts), unless a rank appears
// twice, as in a sweep over --threads: then each count is a point of its own.
std::vector<RankGroup> group_ranks(const ResultFile& f) {
    std::map<PointKey, std::vector<const LoadedPoint*>> by_point;
    std::vector<PointKey> order;
    std::map<PointKey, const LoadedPoint*> aggregates;  // by key without the scope, threads kept
    for (const auto& p : f.points) {
        PointKey k = p.key;
        k.rank_scope.clear();
        if (p.mpi.scope == RankOrigin::Scope::aggregate) aggregates.emplace(k, &p);
        if (p.mpi.scope != RankOrigin::Scope::rank || p.measures.empty()) continue;
        k.threads = 0;
        if (!by_point.count(k)) order.push_back(k);
        by_point[k].push_back(&p);
    }
    std::vector<RankGroup> out;
    for (const auto& k : order) {
        const auto& records = by_point[k];
        std::set<int> seen;
        bool repeated = false;
        for (const auto* p : records) repeated = !seen.insert(p->mpi.rank).second || repeated;
        std::map<int, RankGroup> split;  // by threads where a rank repeats, else one group
        for (const auto* p : records) {
            RankGroup& g = split[repeated ? p->key.threads : 0];
            g.key = k;
            g.by_rank.emplace(p->mpi.rank, p);
        }
        for (auto& [threads, g] : split) {
            PointKey all = g.key;
            all.threads = 0;
            for (const auto& [rank, p] : g.by_rank) all.threads += p->key.threads;
            if (auto it = aggregates.find(all); it != aggregates.end()) g.aggregate = it->second;
            out.push_back(std::move(g));
        }
    }
    return out;
}

// "t=1/rank", or each rank's count where they differ: "t=2,1/rank".
std::string rank_threads_text(const RankGroup& g) {
    std::set<int> counts;
    std::string each;
    for (const auto& [rank, p] : g.by_rank) {
        counts.insert(p->key.threads);
        each.append(each.empty() ? "" : ",").append(std::to_string(p->key.threads));
    }
    return "t=" + (counts.size() == 1 ? std::to_string(*counts.begin()) : each) + "/rank";
}

// A lane's figure at one point: the sum of its ranks' best where higher is better (they ran at
// once), its worst rank's best where lower is better. NAN where a rank of the lane has none.
struct LaneFigure {
    double value = NAN;
    bool verified = true;
};
LaneFigure lane_figure(const RankGroup& g, const Lane& lane, const Measure& head) {
    LaneFigure out;
    double sum = 0, worst = 0;
    for (int rank : lane.ranks) {
        auto it = g.by_rank.find(rank);
        const Measure* m = it == g.by_rank.end() ? nullptr : find_measure(*it->second, head.name);
        if (!m) return out;
        out.verified = out.verified && it->second->verified;
        sum += m->best;
        worst = std::max(worst, m->best);
    }
    out.value = head.direction == Direction::higher_is_better ? sum : worst;
    return out;
}

std::string spread_text(double spread) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.3f", spread);
    return buf;
}

std::string memory_text(std::uint64_t bytes) { return bytes ? format_bytes(bytes) : "?"; }

// The hosts as the context lists them, and the machine fields on which they differ.
std::string hosts_section(const LoadedMpiJob& job, bool markdown) {
    TextTable t{{"host", "ranks", "CPU", "cores", "PUs", "NUMA nodes", "memory"},
                {},
                {false, false, false, true, true, true, true}};
    for (const auto& h : job.hosts) {
        std::string ranks;
        for (int r : h.ranks) ranks.append(ranks.empty() ? "" : ",").append(std::to_string(r));
        t.rows.push_back({h.host, ranks, h.cpu_model.empty() ? "?" : h.cpu_model, std::to_string(h.cores),
                          std::to_string(h.pus), std::to_string(h.numa_node_count), memory_text(h.memory_bytes)});
    }
    std::string differ;
    auto check = [&](const char* name, auto get) {
        for (const auto& h : job.hosts)
            if (get(h) != get(job.hosts.front())) {
                differ += (differ.empty() ? "" : ", ") + std::string(name);
                return;
            }
    };
    check("CPU", [](const LoadedHost& h) { return h.cpu_model; });
    check("cores", [](const LoadedHost& h) { return h.cores; });
    check("PUs", [](const LoadedHost& h) { return h.pus; });
    check("NUMA nodes", [](const LoadedHost& h) { return h.numa_node_count; });
    check("memory", [](const LoadedHost& h) { return h.memory_bytes; });
    std::string out = markdown ? "\n### Hosts\n\n" + t.render_markdown() : "\nHosts:\n" + t.render_text();
    if (job.hosts.size() > 1)
        out += std::string(markdown ? "\n" : "") +
               (differ.empty()
                    ? "The hosts are alike as machines (CPU, cores, PUs, NUMA nodes, memory).\n"
                    : "The hosts differ as machines in: " + differ + " (a difference below may come from that).\n");
    return out;
}

}  // namespace

std::string render_host_comparison(const ResultFile& f, bool markdown) {
    if (!f.mpi)
        throw InputError(f.path +
                         ": a run of one process; compare needs two result files, or one of an MPI run (suite-mpi)");
    const LoadedMpiJob& job = *f.mpi;
    const bool by_host = job.hosts.size() > 1;
    if (!by_host && job.ranks < 2)
        throw InputError(
            f.path +
            ": an MPI run of one rank on one host has no hosts or ranks to line up; compare it with another file");
    std::vector<Lane> lanes;
    if (by_host) {
        for (const auto& h : job.hosts) lanes.push_back({h.host, h.ranks});
    } else {
        for (int r = 0; r < job.ranks; ++r) lanes.push_back({"rank " + std::to_string(r), {r}});
    }
    const std::vector<RankGroup> groups = group_ranks(f);
    if (groups.empty())
        throw InputError(f.path + ": no record of a rank with a figure to line up (is every record an aggregate?)");
    const std::string what = by_host ? "host" : "rank";

    std::string out = markdown ? "## suite compare: the " + what + "s of one MPI run\n\n"
                               : "suite compare: the " + what + "s of one MPI run side by side\n\n";
    {
        // The library's name and version: "Open MPI v4.1.4" of "Open MPI v4.1.4, package: ...".
        const std::string library = job.library.substr(0, job.library.find(','));
        TextTable t{{"path", "machine", "date", "git", "processes", "layout", "MPI", "complete"}, {}, {}};
        t.rows.push_back({f.path, f.machine_label(), context_text(f.context, "date"),
                          context_text(f.context, "git_revision"), f.processes_label(), job.layout,
                          library.empty() ? "?" : library, f.complete ? "yes" : "no (interrupted)"});
        out += markdown ? t.render_markdown() : t.render_text();
    }
    out += hosts_section(job, markdown);

    TextTable table{{"point", "figure"}, {}, {false, false}};
    for (const auto& lane : lanes) {
        const std::size_t n = lane.ranks.size();
        table.header.push_back(by_host ? lane.name + " (" + std::to_string(n) + (n == 1 ? " rank)" : " ranks)")
                                       : lane.name);
        table.header.push_back("vs fastest");
        table.right.insert(table.right.end(), {true, true});
    }
    table.header.insert(table.header.end(), {"slowest", "all ranks", "rank spread"});
    table.right.insert(table.right.end(), {false, true, true});
    std::map<std::string, std::vector<std::vector<double>>> logs;  // per kernel and lane
    std::vector<std::string> kernel_order;
    std::vector<std::size_t> slowest_count(lanes.size(), 0);
    std::size_t named = 0;
    bool unverified = false;
    for (const auto& g : groups) {
        const Measure& head = g.by_rank.begin()->second->measures.front();
        std::vector<LaneFigure> figures;
        double fastest = NAN;
        for (const auto& lane : lanes) {
            figures.push_back(lane_figure(g, lane, head));
            const double v = figures.back().value;
            if (std::isnan(v)) continue;
            if (std::isnan(fastest) || performance_ratio(fastest, v, head.direction) > 1) fastest = v;
        }
        const std::string kernel = g.key.variant.empty() ? g.key.kernel : g.key.kernel + "-" + g.key.variant;
        if (!logs.count(kernel)) {
            kernel_order.push_back(kernel);
            logs[kernel].resize(lanes.size());
        }
        std::vector<std::string> row{g.key.label_with_threads(rank_threads_text(g)), head.name + " " + head.unit};
        std::size_t slowest = lanes.size();
        double slowest_ratio = 1;
        for (std::size_t l = 0; l < lanes.size(); ++l) {
            const double ratio = performance_ratio(fastest, figures[l].value, head.direction);
            if (std::isnan(ratio)) {
                row.insert(row.end(), {"-", "-"});
                continue;
            }
            unverified = unverified || !figures[l].verified;
            row.push_back(compare_value_text(figures[l].value) + (figures[l].verified ? "" : " !"));
            row.push_back(compare_ratio_text(ratio));
            logs[kernel][l].push_back(std::log(ratio));
            // Named only when it is slower as printed (0.999x): equal lanes have no slowest.
            if (ratio < 0.9995 && ratio < slowest_ratio) {
                slowest = l;
                slowest_ratio = ratio;
            }
        }
        if (slowest < lanes.size()) {
            ++slowest_count[slowest];
            ++named;
        }
        row.push_back(slowest < lanes.size() ? lanes[slowest].name : "-");
        const Measure* all = g.aggregate ? find_measure(*g.aggregate, head.name) : nullptr;
        row.push_back(all ? compare_value_text(all->best) + (g.aggregate->verified ? "" : " !") : "-");
        row.push_back(g.aggregate ? spread_text(g.aggregate->mpi.spread) : "-");
        unverified = unverified || (all && !g.aggregate->verified);
        table.rows.push_back(row);
    }

    out += markdown ? "\n### Points\n\n" : "\n";
    out += std::to_string(groups.size()) + " point(s), one column per " + what + ": " +
           (by_host ? "for a figure where higher is better (GB/s) the sum of the best figures of the host's ranks, "
                      "which ran at once; where "
                      "lower is better (ns/load) its worst rank's best"
                    : "the rank's best figure") +
           ". \"vs fastest\": its performance relative to the fastest " + what +
           " at that point, 1.000x for the fastest and below 1 for a slower one, whichever way the figure goes; "
           "\"slowest\": the " +
           what +
           " furthest behind (\"-\" when all are equal). \"all ranks\": the aggregate record (the work of all ranks "
           "over the slowest rank's "
           "time, per repetition); \"rank spread\": its slowest rank's best time over its fastest rank's.\n";
    if (!markdown) out += "\n";
    out += markdown ? "\n" + table.render_markdown() : table.render_text();
    if (unverified) out += "! failed verification on that " + what + ": not a valid result\n";

    TextTable geo{{"kernel"}, {}, {false}};
    for (const auto& lane : lanes) {
        geo.header.insert(geo.header.end(), {lane.name + " vs fastest", "points"});
        geo.right.insert(geo.right.end(), {true, true});
    }
    std::vector<std::vector<double>> everything(lanes.size());
    auto geo_row = [&](const std::string& name, const std::vector<std::vector<double>>& per_lane) {
        std::vector<std::string> row{name};
        for (const auto& v : per_lane) {
            double sum = 0;
            for (double x : v) sum += x;
            row.push_back(v.empty() ? "-" : compare_ratio_text(std::exp(sum / static_cast<double>(v.size()))));
            row.push_back(std::to_string(v.size()));
        }
        geo.rows.push_back(row);
    };
    for (const auto& kernel : kernel_order) {
        geo_row(kernel, logs[kernel]);
        for (std::size_t l = 0; l < lanes.size(); ++l)
            everything[l].insert(everything[l].end(), logs[kernel][l].begin(), logs[kernel][l].end());
    }
    if (kernel_order.size() > 1) geo_row("all kernels", everything);
    out += markdown ? "\n### Geometric mean per kernel\n\n" + geo.render_markdown() + "\n"
                    : "\nGeometric mean of each " + what + "'s ratio to the fastest, per kernel:\n" + geo.render_text();
    if (named) {
        const std::size_t most = static_cast<std::size_t>(std::max_element(slowest_count.begin(), slowest_count.end()) -
                                                          slowest_count.begin());
        out += "Slowest most often: " + lanes[most].name + ", at " + std::to_string(slowest_count[most]) + " of " +
               std::to_string(groups.size()) + " point(s).\n";
    } else {
        out += "No " + what + " is slower than another at any point.\n";
    }
    for (const auto& note : f.notes) out += "note: " + note + "\n";
    return out;
}

}  // namespace suite
