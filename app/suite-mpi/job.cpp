#include "app/suite-mpi/job.hpp"

#include <mpi.h>
#include <sched.h>

#include <algorithm>
#include <map>
#include <set>
#include <stdexcept>

#include "harness/common/units.hpp"
#include "harness/machine/rank_share.hpp"
#include "harness/machine/team.hpp"
#include "harness/machine/topology.hpp"

namespace suite {

namespace {

void bind_process(const std::vector<int>& cpus) {
    cpu_set_t set;
    CPU_ZERO(&set);
    for (int c : cpus) CPU_SET(c, &set);
    if (sched_setaffinity(0, sizeof set, &set) != 0)
        throw std::runtime_error("the OS refused to bind this rank to CPUs " + format_cpu_list(cpus));
}

// Every rank's text in `comm`, in rank order, on every rank of it.
std::vector<std::string> allgather_texts(MPI_Comm comm, const std::string& text) {
    int n = 0;
    MPI_Comm_size(comm, &n);
    int mine = static_cast<int>(text.size());
    std::vector<int> sizes(n), offsets(n);
    MPI_Allgather(&mine, 1, MPI_INT, sizes.data(), 1, MPI_INT, comm);
    int total = 0;
    for (int r = 0; r < n; ++r) offsets[r] = total, total += sizes[r];
    std::string all(static_cast<std::size_t>(total), '\0');
    MPI_Allgatherv(text.data(), mine, MPI_CHAR, all.data(), sizes.data(), offsets.data(), MPI_CHAR, comm);
    std::vector<std::string> out;
    for (int r = 0; r < n; ++r)
        out.push_back(all.substr(static_cast<std::size_t>(offsets[r]), static_cast<std::size_t>(sizes[r])));
    return out;
}

std::string library_version() {
    char text[MPI_MAX_LIBRARY_VERSION_STRING];
    int len = 0;
    MPI_Get_library_version(text, &len);
    std::string v(text, static_cast<std::size_t>(std::max(0, len)));
    if (const auto nl = v.find('\n'); nl != std::string::npos) v.resize(nl);
    while (!v.empty() && (v.back() == ',' || v.back() == ' ' || v.back() == '\0')) v.pop_back();
    return v;
}

}  // namespace

std::string broadcast_text(const std::string& text) {
    int n = static_cast<int>(text.size());
    MPI_Bcast(&n, 1, MPI_INT, 0, MPI_COMM_WORLD);
    std::string out = text;
    out.resize(static_cast<std::size_t>(n));
    MPI_Bcast(out.data(), n, MPI_CHAR, 0, MPI_COMM_WORLD);
    return out;
}

std::vector<std::string> gather_texts(const std::string& text) {
    int rank = 0, n = 0;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &n);
    int mine = static_cast<int>(text.size());
    std::vector<int> sizes(rank == 0 ? n : 0), offsets(rank == 0 ? n : 0);
    MPI_Gather(&mine, 1, MPI_INT, sizes.data(), 1, MPI_INT, 0, MPI_COMM_WORLD);
    int total = 0;
    for (int r = 0; r < static_cast<int>(sizes.size()); ++r) offsets[r] = total, total += sizes[r];
    std::string all(static_cast<std::size_t>(total), '\0');
    MPI_Gatherv(text.data(), mine, MPI_CHAR, all.data(), sizes.data(), offsets.data(), MPI_CHAR, 0, MPI_COMM_WORLD);
    std::vector<std::string> out;
    for (int r = 0; r < static_cast<int>(sizes.size()); ++r)
        out.push_back(all.substr(static_cast<std::size_t>(offsets[r]), static_cast<std::size_t>(sizes[r])));
    return out;
}

Job start_job() {
    Job job;
    MPI_Comm_rank(MPI_COMM_WORLD, &job.rank);
    MPI_Comm_size(MPI_COMM_WORLD, &job.size);
    char name[MPI_MAX_PROCESSOR_NAME];
    int len = 0;
    MPI_Get_processor_name(name, &len);
    job.host.assign(name, static_cast<std::size_t>(std::max(0, len)));

    // The ranks of this host, and the masks the launcher started them with.
    MPI_Comm local;
    MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, job.rank, MPI_INFO_NULL, &local);
    int local_rank = 0, local_size = 1;
    MPI_Comm_rank(local, &local_rank);
    MPI_Comm_size(local, &local_size);
    const std::string my_mask = format_cpu_list(current_cpuset());
    const std::vector<std::string> masks = allgather_texts(local, my_mask);
    int group = 0, index = 0;  // ranks of this host started with my mask, and my place among them
    for (int r = 0; r < local_size; ++r)
        if (masks[r] == my_mask) (r < local_rank ? ++index : 0), ++group;

    // My share: what the launcher gave me if it gave each rank its own mask, else my part of ours.
    std::string problem, layout;
    try {
        const Topology under_mask = Topology::load();
        if (group == 1 && local_size > 1) {
            job.cpus = under_mask.mask_cpus.empty() ? current_cpuset() : under_mask.mask_cpus;
            layout = "given";
        } else {
            RankShare share = share_of(under_mask, group, index);
            job.cpus = std::move(share.cpus);
            layout = share.layout;
        }
        bind_process(job.cpus);
        Topology::adopt_mask(job.cpus);
    } catch (const std::exception& e) {
        problem = job.host + ": " + e.what();
    }
    // The sets as bound, checked for overlap on each host.
    const std::vector<std::string> bound =
        allgather_texts(local, problem.empty() ? format_cpu_list(current_cpuset()) : "");
    std::vector<int> local_to_world(static_cast<std::size_t>(local_size));
    MPI_Allgather(&job.rank, 1, MPI_INT, local_to_world.data(), 1, MPI_INT, local);
    if (problem.empty()) {
        std::vector<std::vector<int>> sets;
        for (const auto& b : bound) sets.push_back(b.empty() ? std::vector<int>{} : parse_cpu_list(b));
        std::string clash;
        if (!disjoint_sets(sets, local_to_world, clash))
            problem = job.host + ": the ranks' CPU sets overlap (" + clash +
                      "); start them unbound (mpirun --bind-to none) or bound to disjoint sets";
    }
    MPI_Comm_free(&local);

    // What each rank is, on rank 0: the context's hosts, or the first problem.
    const Topology whole = Topology::load(true);
    std::vector<int> nodes;
    for (const Pu& pu : whole.pus)
        if (std::find(job.cpus.begin(), job.cpus.end(), pu.os_index) != job.cpus.end() &&
            std::find(nodes.begin(), nodes.end(), pu.numa_node) == nodes.end() && pu.numa_node >= 0)
            nodes.push_back(pu.numa_node);
    std::sort(nodes.begin(), nodes.end());
    const nlohmann::json me = {{"rank", job.rank},
                               {"host", job.host},
                               {"cpus", format_cpu_list(job.cpus)},
                               {"numa_nodes", nodes},
                               {"layout", layout},
                               {"problem", problem},
                               {"cpu_model", whole.cpu_model},
                               {"cores", std::max(1, whole.cores)},
                               {"pus", std::max(1, whole.pu_count())},
                               {"numa_node_count", static_cast<int>(whole.nodes.size())},
                               {"memory_bytes", whole.memory_bytes}};
    const std::vector<std::string> all = gather_texts(me.dump());
    std::string refusal;
    if (job.rank == 0) {
        std::map<std::string, nlohmann::json> hosts;
        std::vector<std::string> host_order;
        std::set<std::string> layouts;
        for (const auto& text : all) {
            const nlohmann::json r = nlohmann::json::parse(text);
            if (refusal.empty() && !r["problem"].get<std::string>().empty()) refusal = r["problem"].get<std::string>();
            const std::string h = r["host"];
            layouts.insert(r["layout"].get<std::string>());
            if (!hosts.count(h)) {
                host_order.push_back(h);
                hosts[h] = {{"host", h},
                            {"ranks", nlohmann::json::array()},
                            {"cpus", nlohmann::json::array()},
                            {"numa_nodes", nlohmann::json::array()},
                            {"disjoint", true},
                            {"cpu_model", r["cpu_model"]},
                            {"cores", r["cores"]},
                            {"pus", r["pus"]},
                            {"numa_node_count", r["numa_node_count"]},
                            {"memory_bytes", r["memory_bytes"]}};
            }
            hosts[h]["ranks"].push_back(r["rank"]);
            hosts[h]["cpus"].push_back(r["cpus"]);
            hosts[h]["numa_nodes"].push_back(r["numa_nodes"]);
        }
        nlohmann::json list = nlohmann::json::array();
        for (const auto& h : host_order) list.push_back(hosts[h]);
        const std::string overall = layouts.size() == 1 ? *layouts.begin() : "split";
        job.context = {{"library", library_version()}, {"ranks", job.size}, {"layout", overall}, {"hosts", list}};
    }
    int hosts = static_cast<int>(job.context.is_null() ? 0 : job.context["hosts"].size());
    MPI_Bcast(&hosts, 1, MPI_INT, 0, MPI_COMM_WORLD);
    job.hosts = hosts;
    refusal = broadcast_text(refusal);
    if (!refusal.empty()) {
        JobRefused e;
        if (job.rank == 0) e.message = refusal;
        throw e;
    }
    return job;
}

}  // namespace suite
