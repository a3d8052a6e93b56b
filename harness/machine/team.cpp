#include "harness/machine/team.hpp"

#include <omp.h>
#include <pthread.h>
#include <sched.h>

#include <algorithm>
#include <cctype>
#include <cstring>
#include <map>
#include <set>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "harness/common/did_you_mean.hpp"
#include "harness/common/units.hpp"
#include "harness/kernel/kernel.hpp"  // require_team_size

namespace suite {

namespace {

// The CPU set the process started with: PinMode::none gives it back to every thread, so a
// point pinned earlier in a sweep does not leak its binding into an unpinned one.
cpu_set_t initial_cpuset() {
    static const cpu_set_t set = [] {
        cpu_set_t s;
        CPU_ZERO(&s);
        sched_getaffinity(0, sizeof s, &s);
        return s;
    }();
    return set;
}

}  // namespace

std::vector<int> current_cpuset() {
    cpu_set_t got;
    CPU_ZERO(&got);
    pthread_getaffinity_np(pthread_self(), sizeof got, &got);
    std::vector<int> cpus;
    for (int c = 0; c < CPU_SETSIZE; ++c)
        if (CPU_ISSET(c, &got)) cpus.push_back(c);
    return cpus;
}

const ChoiceTable<PinMode>& pin_modes() {
    static const ChoiceTable<PinMode> table{
        "--pin value",
        {{"compact", "one thread a core, filling a package before the next, then the cores' second hyperthreads",
          PinMode::compact},
         {"scatter", "one thread a core, cores dealt round-robin over the NUMA nodes", PinMode::scatter},
         {"none", "threads not pinned: each may run anywhere in the process's CPU set", PinMode::none}}};
    return table;
}

const std::string& pin_name(PinMode m) {
    for (const auto& c : pin_modes().all())
        if (c.what == m) return c.name;
    throw std::logic_error("--pin: a mode without a name (a CPU list has none)");
}

std::string pin_forms() { return pin_modes().accepted() + ", or a CPU list such as 0,2,4-7"; }

PinSpec parse_pin(std::string_view text, const Topology& topo) {
    PinSpec spec;
    spec.text = std::string(text);
    if (const Choice<PinMode>* named = pin_modes().find(text))
        spec.mode = named->what;
    else if (!text.empty() && std::isdigit(static_cast<unsigned char>(text[0]))) {
        spec.mode = PinMode::list;
        spec.cpus = parse_cpu_list(text);
        for (int c : spec.cpus) {
            if (!topo.find_pu(c) &&
                std::find(topo.machine_cpus.begin(), topo.machine_cpus.end(), c) != topo.machine_cpus.end())
                throw UsageError("--pin=" + spec.text + ": CPU " + std::to_string(c) +
                                 " is outside this process's CPU mask " + format_cpu_list(topo.mask_cpus) +
                                 " (set by taskset, a cgroup or the batch scheduler); pin to CPUs in the mask");
            if (!topo.find_pu(c) || c >= CPU_SETSIZE)
                throw UsageError("--pin list names CPU " + std::to_string(c) +
                                 ", which this machine does not have (it has " + std::to_string(topo.pu_count()) +
                                 " PUs; see ./suite info)");
        }
    } else {
        std::string hint = nearest(text, pin_modes().names());
        throw UsageError("unknown " + pin_modes().what() + " '" + std::string(text) + "'" +
                         (hint.empty() ? "" : " (did you mean '" + hint + "'?)") + "; accepted: " + pin_forms());
    }
    initial_cpuset();  // remember the original set before anything is pinned
    return spec;
}

std::vector<int> pin_order(const Topology& topo, const PinSpec& spec) {
    if (spec.mode == PinMode::none) return {};
    if (spec.mode == PinMode::list) return spec.cpus;
    int max_smt = 0;
    for (const auto& p : topo.pus) max_smt = std::max(max_smt, p.smt_rank);
    std::vector<int> order;
    for (int rank = 0; rank <= max_smt; ++rank) {
        std::vector<const Pu*> layer;
        for (const auto& p : topo.pus)
            if (p.smt_rank == rank) layer.push_back(&p);
        std::stable_sort(layer.begin(), layer.end(), [](const Pu* a, const Pu* b) { return a->core < b->core; });
        if (spec.mode == PinMode::compact) {
            for (const Pu* p : layer) order.push_back(p->os_index);
            continue;
        }
        // scatter: deal the cores out node by node.
        std::map<int, std::vector<int>> by_node;
        for (const Pu* p : layer) by_node[p->numa_node].push_back(p->os_index);
        for (std::size_t k = 0; order.size() < topo.pus.size(); ++k) {
            bool any = false;
            for (auto& [node, cpus] : by_node)
                if (k < cpus.size()) {
                    order.push_back(cpus[k]);
                    any = true;
                }
            if (!any) break;
        }
    }
    return order;
}

std::vector<ThreadBinding> bind_team(const Topology& topo, const PinSpec& spec, int threads) {
    const std::vector<int> order = pin_order(topo, spec);
    if (spec.mode != PinMode::none && static_cast<int>(order.size()) < threads)
        throw UsageError("--pin=" + spec.text + " gives " + std::to_string(order.size()) + " CPU(s) but " +
                         std::to_string(threads) + " threads were asked for");
    omp_set_dynamic(0);
    omp_set_num_threads(threads);
    std::vector<ThreadBinding> team(threads);
    std::vector<std::string> errors(threads);
    const cpu_set_t original = initial_cpuset();
    int team_size = 0;
#pragma omp parallel num_threads(threads)
    {
        const int t = omp_get_thread_num();
#pragma omp single
        team_size = omp_get_num_threads();
        cpu_set_t set;
        if (spec.mode == PinMode::none) {
            set = original;
        } else {
            CPU_ZERO(&set);
            CPU_SET(order[t], &set);
            team[t].requested_cpu = order[t];
        }
        if (int rc = pthread_setaffinity_np(pthread_self(), sizeof set, &set); rc != 0)
            errors[t] = "cannot pin thread " + std::to_string(t) + " to CPU " +
                        std::to_string(order.empty() ? -1 : order[t]) + ": " + std::strerror(rc);
        sched_yield();  // let the scheduler move us before reading back where we are
        team[t].allowed = current_cpuset();
        team[t].thread = t;
        team[t].cpu = sched_getcpu();
    }
    require_team_size(team_size, threads);
    for (const auto& e : errors)
        if (!e.empty()) throw std::runtime_error(e);
    for (auto& b : team)
        if (const Pu* pu = topo.find_pu(b.cpu)) b.numa_node = pu->numa_node;
    return team;
}

bool team_still_bound(const std::vector<ThreadBinding>& team) {
    const int threads = static_cast<int>(team.size());
    int moved = 0;
#pragma omp parallel num_threads(threads) reduction(+ : moved)
    {
        const int t = omp_get_thread_num();
        if (t >= threads || current_cpuset() != team[t].allowed) moved += 1;
    }
    return moved == 0;
}

nlohmann::json to_json(const ThreadBinding& b) {
    // Unknown or not applicable is null, never -1.
    auto known = [](int v) { return v >= 0 ? nlohmann::json(v) : nlohmann::json(nullptr); };
    return {{"thread", b.thread},
            {"allowed_cpus", b.allowed},
            {"requested_cpu", known(b.requested_cpu)},
            {"cpu", known(b.cpu)},
            {"numa_node", known(b.numa_node)}};
}

}  // namespace suite
