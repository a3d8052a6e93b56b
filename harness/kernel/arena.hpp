#pragma once
// The memory a kernel gets: an Arena hands out page-aligned arrays with one MemoryPolicy (which
// node, interleaved or first touch, huge pages or not) applied before any page is touched, and
// afterwards says where each array's pages really landed (move_pages, /proc/self/smaps). It is
// part of the kernel contract because every kernel allocates through it; which policy to apply
// is decided by harness/machine/placement, from what the user asked for.
#include <cstddef>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

namespace suite {

enum class PlacementKind { local, node, remote, interleave };

// Transparent huge pages for an Arena's arrays: leave the system's setting alone, ask for
// them (madvise MADV_HUGEPAGE, with each array aligned to 2 MiB), or refuse them
// (MADV_NOHUGEPAGE); the advice is given before the first touch, which is when pages are made.
enum class HugePages { system, thp, none };
const char* hugepages_name(HugePages h);

// What an Arena does with fresh pages: nothing (first touch decides), bind to one node, or
// interleave over a set of nodes; and whether to advise huge pages.
struct MemoryPolicy {
    PlacementKind kind = PlacementKind::local;
    int node = -1;
    std::vector<int> nodes;  // interleave set
    HugePages hugepages = HugePages::system;
};

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
std::optional<std::uint64_t> anon_huge_bytes_in_smaps(const std::string& smaps, std::uintptr_t start,
                                                      std::uintptr_t end);

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
// target node's free memory for node/remote; never more than an address-space limit
// (RLIMIT_AS, `ulimit -v`) leaves beyond what is mapped already. Every estimate before a run
// is held against this one number.
std::uint64_t available_memory_bytes(const MemoryPolicy& policy);

}  // namespace suite
