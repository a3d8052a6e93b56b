#pragma once
// Where an array's pages live. A PlacementSpec is what the user asked for; resolve_policy()
// turns it, given the CPUs the team may run on, into the one policy an Arena applies to every
// array it hands out. After the kernel's first touch, Arena::observe() asks the kernel (move_pages)
// where each page really is, so the result records what happened, not just what was asked.
#include <cstddef>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "harness/topology.hpp"

namespace suite {

enum class PlacementKind { local, node, remote, interleave };

struct PlacementSpec {
    PlacementKind kind = PlacementKind::local;
    int node = -1;     // for PlacementKind::node
    std::string text;  // as given
};

// "local" | "node:N" | "remote" | "interleave". Throws UsageError for a node that does not
// exist and for "remote" on a machine with one NUMA node.
PlacementSpec parse_placement(std::string_view text, const Topology& topo);

// The node that "remote" places arrays on: one that none of `thread_nodes` is, the nearest of
// those by NUMA distance to the threads (the usual one-hop "scenario A"), lowest index on ties.
// -1 when the threads cover every node.
int choose_remote_node(const Topology& topo, const std::vector<int>& thread_nodes);

// Transparent huge pages for an Arena's arrays: leave the system's setting alone, ask for
// them (madvise MADV_HUGEPAGE, with each array aligned to 2 MiB), or refuse them
// (MADV_NOHUGEPAGE); the advice is given before the first touch, which is when pages are made.
enum class HugePages { system, thp, none };

// "thp" | "none" | "system". Throws UsageError for anything else, and for "thp" where the
// kernel has no transparent huge pages (no `thp_enabled` file, the kernel's unless a test names
// another: madvise would fail); where they are switched off ("never") it sets `note`.
HugePages parse_hugepages(std::string_view text, const std::string& thp_enabled = "/sys/kernel/mm/transparent_hugepage/enabled",
                          std::string* note = nullptr);
const char* hugepages_name(HugePages h);

// What an Arena does with fresh pages: nothing (first touch decides), bind to one node, or
// interleave over a set of nodes; and whether to advise huge pages.
struct MemoryPolicy {
    PlacementKind kind = PlacementKind::local;
    int node = -1;
    std::vector<int> nodes;  // interleave set
    HugePages hugepages = HugePages::system;
};

// The policy of `spec` for threads that may run on `thread_cpus` (OS CPU numbers). Throws
// UsageError when "remote" has no node left that the threads do not use.
MemoryPolicy resolve_policy(const PlacementSpec& spec, const Topology& topo, const std::vector<int>& thread_cpus);

struct ArrayPlacement {
    std::string name;
    std::uint64_t bytes = 0;
    std::uint64_t pages = 0;
    std::map<int, std::uint64_t> pages_per_node;
    std::uint64_t pages_not_present = 0;  // never touched, or the query failed
    std::string error;                    // why the query failed, if it did
    // Bytes of the array backed by transparent huge pages (AnonHugePages of its mapping in
    // /proc/self/smaps); unset with huge_error when that could not be read.
    std::optional<std::uint64_t> anon_huge_bytes;
    std::string huge_error;
};

// AnonHugePages, in bytes, of the mapping that spans exactly [start, end) in the text of a
// /proc/PID/smaps file; unset when no mapping has those bounds or it has no such line.
std::optional<std::uint64_t> anon_huge_bytes_in_smaps(const std::string& smaps, std::uintptr_t start, std::uintptr_t end);

// Owns the arrays of one measured point: page-aligned mmap memory, with the point's policy
// applied before any page is touched. Each array is its own mapping between two inaccessible
// guard pages, so that the kernel never merges it with a neighbour and /proc/self/smaps can
// say how much of exactly that array huge pages back. Move-only; frees everything on destruction.
class Arena {
public:
    explicit Arena(MemoryPolicy policy);
    ~Arena();
    Arena(Arena&& other) noexcept;
    Arena& operator=(Arena&&) = delete;
    Arena(const Arena&) = delete;
    Arena& operator=(const Arena&) = delete;

    // Untouched memory for `count` objects of T: the kernel's setup touches it first, from the
    // threads and with the schedule that compute on it.
    template <class T>
    T* allocate(const std::string& name, std::size_t count) {
        return static_cast<T*>(allocate_bytes(name, count * sizeof(T)));
    }
    void* allocate_bytes(const std::string& name, std::size_t bytes);

    std::vector<ArrayPlacement> observe() const;

private:
    struct Block {
        std::string name;
        void* ptr;           // the array
        std::size_t bytes;   // its length, whole pages
        void* mapping;       // the whole mapping, guard pages included
        std::size_t mapped;  // its length
    };
    MemoryPolicy policy_;
    std::vector<Block> blocks_;
};

nlohmann::json to_json(const ArrayPlacement& a);

// Bytes of memory this process could still get: MemAvailable for local/interleave, the
// target node's free memory for node/remote.
std::uint64_t available_memory_bytes(const MemoryPolicy& policy);

}  // namespace suite
