#pragma once
// How the ranks of an MPI job that land on one host share its CPUs without overlap (suite-mpi).
// The launcher starts them with some CPU mask each; the ranks whose masks are identical split
// that mask between them: one rank per NUMA node when there are exactly as many of them as
// nodes under the mask (the documented layout: each rank's threads and first-touch pages then
// stay on its node), otherwise equal runs of whole cores in hwloc's order. No MPI here: the
// MPI layer gathers the masks and calls this, and the tests call it on synthetic machines.
#include <string>
#include <vector>

#include "harness/machine/topology.hpp"

namespace suite {

struct RankShare {
    std::vector<int> cpus;  // OS indexes, ascending
    std::string layout;     // "numa" or "split"
};

// The share of rank `index` of the `ranks` ranks that were started with the same mask, where
// `topo` is the machine under that mask (Topology::load() in one of them). Throws UsageError
// when there are more ranks than cores: ranks would share a core, and their numbers would say
// nothing about the host.
RankShare share_of(const Topology& topo, int ranks, int index);

// Whether no CPU appears in two of the sets; `clash` gets "rank A and rank B both have CPU C"
// for the first overlap found, set s being rank rank_of_set[s].
bool disjoint_sets(const std::vector<std::vector<int>>& sets, const std::vector<int>& rank_of_set, std::string& clash);

}  // namespace suite
