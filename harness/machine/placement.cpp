#include "harness/machine/placement.hpp"

#include <algorithm>
#include <limits>
#include <stdexcept>

#include "harness/common/did_you_mean.hpp"
#include "harness/common/sysfs_file.hpp"
#include "harness/common/text.hpp"
#include "harness/common/units.hpp"
#include "harness/kernel/hugepage_modes.hpp"

namespace suite {

namespace {

// What a user writes for `c`: its name, with ":N" where it takes a node.
std::string form(const Choice<PlacementBehaviour>& c) { return c.what.takes_node ? c.name + ":N" : c.name; }

}  // namespace

const ChoiceTable<PlacementBehaviour>& placement_kinds() {
    static const ChoiceTable<PlacementBehaviour> table{
        "--placement",
        {{"local", "first touch: each page on the node of the thread that first writes it", {PlacementKind::local}},
         {"node", "node:N, every array on NUMA node N", {PlacementKind::node, true}},
         {"remote", "every array on the nearest node that none of the threads runs on", {PlacementKind::remote}},
         {"interleave", "pages dealt round-robin over all NUMA nodes", {PlacementKind::interleave}}}};
    return table;
}

const std::string& placement_name(PlacementKind k) {
    for (const auto& c : placement_kinds().all())
        if (c.what.kind == k) return c.name;
    throw std::logic_error("--placement: a kind without a name");
}

std::string placement_forms() {
    std::vector<std::string> forms;
    for (const auto& c : placement_kinds().all()) forms.push_back(form(c));
    return join(forms, ", ");
}

std::string placement_forms_other_than(PlacementKind k) {
    std::vector<std::string> forms;
    for (const auto& c : placement_kinds().all())
        if (c.what.kind != k) forms.push_back(form(c));
    const std::string last = forms.back();
    forms.pop_back();
    return forms.empty() ? last : join(forms, ", ") + " or " + last;
}

PlacementSpec parse_placement(std::string_view text, const Topology& topo) {
    PlacementSpec spec;
    spec.text = std::string(text);
    const std::size_t colon = text.find(':');
    const Choice<PlacementBehaviour>* c = placement_kinds().find(text.substr(0, colon));
    if (!c || c->what.takes_node != (colon != std::string_view::npos)) {
        std::vector<std::string> candidates;  // node:0 for node:N, as a user would write it
        for (const auto& k : placement_kinds().all()) candidates.push_back(k.what.takes_node ? k.name + ":0" : k.name);
        std::string hint = nearest(text, candidates);
        throw UsageError("unknown " + placement_kinds().what() + " '" + std::string(text) + "'" +
                         (hint.empty() ? "" : " (did you mean '" + hint + "'?)") + "; accepted: " + placement_forms());
    }
    spec.kind = c->what.kind;
    if (spec.kind == PlacementKind::remote && topo.nodes.size() < 2)
        throw UsageError("--placement=" + spec.text + " needs at least 2 NUMA nodes, and this machine has " +
                         std::to_string(topo.nodes.size()) + "; use " + placement_forms_other_than(spec.kind));
    if (!c->what.takes_node) return spec;
    const std::string n(text.substr(colon + 1));
    const auto node = whole_number(n);
    if (!node)
        throw UsageError("invalid --placement '" + spec.text + "': expected " + form(*c) + " with N a node number (a " +
                         "whole number from 0), e.g. " + c->name + ":0");
    // A number no node has is still a number: said so below, with the nodes there are.
    spec.node = *node > static_cast<std::uint64_t>(std::numeric_limits<int>::max()) ? -1 : static_cast<int>(*node);
    if (spec.node < 0 || !topo.find_node(spec.node)) {
        std::string have;
        for (const auto& node : topo.nodes) {
            if (!have.empty()) have += ',';
            have += std::to_string(node.os_index);
        }
        throw UsageError("--placement=" + spec.text + ": this machine has no NUMA node " + n + " (its nodes are " +
                         have + ")");
    }
    return spec;
}

int choose_remote_node(const Topology& topo, const std::vector<int>& thread_nodes) {
    int best = -1;
    long best_distance = std::numeric_limits<long>::max();
    for (std::size_t i = 0; i < topo.nodes.size(); ++i) {
        int candidate = topo.nodes[i].os_index;
        if (std::find(thread_nodes.begin(), thread_nodes.end(), candidate) != thread_nodes.end()) continue;
        long distance = 0;  // summed distance from the threads' nodes
        if (!topo.distances.empty()) {
            for (int tn : thread_nodes)
                for (std::size_t k = 0; k < topo.nodes.size(); ++k)
                    if (topo.nodes[k].os_index == tn) distance += topo.distances[k][i];
        }
        if (distance < best_distance) {
            best_distance = distance;
            best = candidate;
        }
    }
    return best;
}

MemoryPolicy resolve_policy(const PlacementSpec& spec, const Topology& topo, const std::vector<int>& thread_cpus) {
    MemoryPolicy policy;
    policy.kind = spec.kind;
    switch (spec.kind) {
        case PlacementKind::local:
            break;
        case PlacementKind::node:
            policy.node = spec.node;
            break;
        case PlacementKind::interleave:
            for (const auto& n : topo.nodes) policy.nodes.push_back(n.os_index);
            break;
        case PlacementKind::remote: {
            std::vector<int> used;  // every node a thread may run on counts as the threads' own
            for (int cpu : thread_cpus)
                if (const Pu* pu = topo.find_pu(cpu);
                    pu && std::find(used.begin(), used.end(), pu->numa_node) == used.end())
                    used.push_back(pu->numa_node);
            policy.node = choose_remote_node(topo, used);
            if (policy.node < 0)
                throw UsageError(
                    "--placement=remote: the threads may run on every NUMA node, so no node is remote to them; "
                    "use fewer threads or pin them to one node's CPUs (--pin=compact or a CPU list)");
            break;
        }
    }
    return policy;
}

HugePages parse_hugepages(std::string_view text, const std::string& path, std::string* note) {
    const HugePages mode = hugepage_modes().at(text).what;
    if (mode != HugePages::thp) return mode;
    const AttributeText enabled = read_attribute(path);
    if (!enabled.ok)
        throw UsageError("--hugepages=thp: this kernel offers no transparent huge pages (" + enabled.reason +
                         "); use none or system");
    const std::string& line = enabled.text;
    // Switched off, madvise still succeeds and simply gets no huge pages: the run goes on, says so
    // first, and its records show how many bytes huge pages backed (none).
    if (line.find("[never]") != std::string::npos && note)
        *note = "--hugepages=thp: transparent huge pages are switched off here (" + path +
                " says never), so the arrays get none; the records say so (hugepages.anon_huge_bytes)";
    return HugePages::thp;
}

}  // namespace suite
