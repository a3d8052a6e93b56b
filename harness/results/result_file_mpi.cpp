// The MPI part of the result-file reader: context.mpi (the job's ranks and hosts) and each
// record's `mpi` (which rank measured it, or the aggregate of all ranks), checked against each
// other, so that `compare` and `check` can line ranks and hosts up without guessing.
#include <set>

#include "harness/results/result_fields.hpp"

namespace suite {

using nlohmann::json;

std::string rank_scope_text(int rank, int ranks) {
    if (rank >= 0) return "rank " + std::to_string(rank) + " of " + std::to_string(ranks);
    return "aggregate of " + std::to_string(ranks) + (ranks == 1 ? " rank" : " ranks");
}

PointKey matching_key(const PointKey& key) {
    PointKey k = key;
    if (k.rank_scope == rank_scope_text(-1, 1)) k.rank_scope.clear();
    return k;
}

const LoadedHost* LoadedMpiJob::host_of(int rank) const {
    for (const auto& h : hosts)
        for (int r : h.ranks)
            if (r == rank) return &h;
    return nullptr;
}

std::string ResultFile::processes_label() const {
    if (!mpi) return "one process";
    return std::to_string(mpi->ranks) + (mpi->ranks == 1 ? " MPI rank" : " MPI ranks") + " on " +
           std::to_string(mpi->hosts.size()) + (mpi->hosts.size() == 1 ? " host" : " hosts");
}

std::optional<LoadedMpiJob> read_mpi_job(const FieldReader& r, const json& context) {
    auto it = context.find("mpi");
    if (it == context.end() || it->is_null()) return std::nullopt;
    const std::string at = "context.mpi";
    if (!it->is_object()) r.fail(at, "expected an object");
    LoadedMpiJob job;
    job.library = r.string(*it, "library", at, true);
    job.layout = r.string(*it, "layout", at);
    job.ranks = r.small_count(*it, "ranks", at, 1);
    const json& hosts = r.field(*it, "hosts", at);
    if (!hosts.is_array() || hosts.empty()) r.fail(at + ".hosts", "expected a non-empty array");
    std::set<int> placed;
    std::set<std::string> names;
    for (std::size_t i = 0; i < hosts.size(); ++i) {
        const std::string hat = at + ".hosts[" + std::to_string(i) + "]";
        LoadedHost h;
        h.host = r.string(hosts[i], "host", hat);
        if (!names.insert(h.host).second) r.fail(hat + ".host", "'" + h.host + "' is listed twice");
        const json& ranks = r.field(hosts[i], "ranks", hat);
        if (!ranks.is_array() || ranks.empty()) r.fail(hat + ".ranks", "expected a non-empty array of ranks");
        for (std::size_t k = 0; k < ranks.size(); ++k) {
            const std::string rat = hat + ".ranks[" + std::to_string(k) + "]";
            const std::uint64_t rank = r.count(ranks[k], rat, 0);
            if (rank >= static_cast<std::uint64_t>(job.ranks))
                r.fail(rat, "rank " + std::to_string(rank) + " of a run of " + std::to_string(job.ranks));
            if (!placed.insert(static_cast<int>(rank)).second)
                r.fail(rat, "rank " + std::to_string(rank) + " is on two hosts");
            h.ranks.push_back(static_cast<int>(rank));
        }
        h.cpu_model = r.string(hosts[i], "cpu_model", hat, true);
        h.cores = r.small_count(hosts[i], "cores", hat, 1);
        h.pus = r.small_count(hosts[i], "pus", hat, 1);
        h.numa_node_count = r.small_count(hosts[i], "numa_node_count", hat, 0);
        h.memory_bytes = r.count(hosts[i], "memory_bytes", hat, 0);
        job.hosts.push_back(std::move(h));
    }
    if (placed.size() != static_cast<std::size_t>(job.ranks)) {
        int missing = 0;
        while (placed.count(missing)) ++missing;
        r.fail(at + ".hosts",
               "rank " + std::to_string(missing) + " of " + std::to_string(job.ranks) + " is on no host");
    }
    return job;
}

RankOrigin read_rank_origin(const FieldReader& r, const json& rec, const std::string& where,
                            const std::optional<LoadedMpiJob>& job) {
    RankOrigin o;
    const std::string at = where + ".mpi";
    auto it = rec.find("mpi");
    if (it == rec.end() || it->is_null()) {
        // Every record of an MPI run says which rank measured it: a record without is not one
        // that suite-mpi wrote, and would meet a plain run's point as if one process had run it.
        if (job) r.fail(at, "missing, in a run of " + std::to_string(job->ranks) + " MPI ranks (context.mpi)");
        return o;
    }
    if (!it->is_object()) r.fail(at, "expected an object");
    if (!job) r.fail(at, "a record of an MPI run, but the context has no mpi (the job's ranks and hosts)");
    const std::string scope = r.string(*it, "scope", at);
    o.ranks = r.small_count(*it, "ranks", at, 1);
    if (o.ranks != job->ranks)
        r.fail(at + ".ranks", std::to_string(o.ranks) + ", but context.mpi.ranks is " + std::to_string(job->ranks));
    auto rank_of = [&](const char* key) {
        const int rank = r.small_count(*it, key, at, 0);
        if (rank >= o.ranks)
            r.fail(at + "." + key, "rank " + std::to_string(rank) + " of a run of " + std::to_string(o.ranks));
        return rank;
    };
    // The host a record names must be the one context.mpi puts that rank on.
    auto host_of = [&](const char* key, int rank) {
        std::string host = r.string(*it, key, at);
        const LoadedHost* h = job->host_of(rank);
        if (h->host != host)
            r.fail(at + "." + key,
                   "'" + host + "', but context.mpi.hosts puts rank " + std::to_string(rank) + " on '" + h->host + "'");
        return host;
    };
    if (scope == "rank") {
        o.scope = RankOrigin::Scope::rank;
        o.rank = rank_of("rank");
        o.host = host_of("host", o.rank);
    } else if (scope == "aggregate") {
        o.scope = RankOrigin::Scope::aggregate;
        o.hosts = r.small_count(*it, "hosts", at, 1);
        if (o.hosts != static_cast<int>(job->hosts.size()))
            r.fail(at + ".hosts",
                   std::to_string(o.hosts) + ", but context.mpi lists " + std::to_string(job->hosts.size()));
        o.slowest_rank = rank_of("slowest_rank");
        o.slowest_host = host_of("slowest_host", o.slowest_rank);
        o.spread = r.number(*it, "spread", at);
        if (o.spread < 1)
            r.fail(at + ".spread", "expected at least 1 (the slowest rank's best time over the fastest rank's)");
    } else {
        r.fail(at + ".scope", "expected 'rank' or 'aggregate'");
    }
    return o;
}

}  // namespace suite
