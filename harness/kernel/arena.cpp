#include "harness/kernel/arena.hpp"

#include <sys/resource.h>

#include <numa.h>
#include <numaif.h>
#include <sys/mman.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <sstream>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "harness/common/units.hpp"
#include "harness/kernel/hugepage_modes.hpp"

namespace suite {

const ChoiceTable<HugePages>& hugepage_modes() {
    static const ChoiceTable<HugePages> table{
        "--hugepages",
        {{"thp", "advise transparent huge pages for every array", HugePages::thp},
         {"none", "refuse them for every array", HugePages::none},
         {"system", "the default: leave the system's THP setting, which ./suite info shows", HugePages::system}}};
    return table;
}

const char* hugepages_name(HugePages h) {
    for (const auto& c : hugepage_modes().all())
        if (c.what == h) return c.name.c_str();
    throw std::logic_error("--hugepages: a mode without a name");
}

Arena::Arena(MemoryPolicy policy) : policy_(std::move(policy)) {}

Arena::Arena(Arena&& other) noexcept : policy_(std::move(other.policy_)), blocks_(std::move(other.blocks_)) {
    other.blocks_.clear();
}

Arena::~Arena() {
    for (const auto& b : blocks_) munmap(b.mapping, b.mapped);
}

void* Arena::allocate_bytes(const std::string& name, std::size_t bytes) {
    const std::size_t page = static_cast<std::size_t>(sysconf(_SC_PAGESIZE));
    std::size_t len = std::max<std::size_t>(page, (bytes + page - 1) / page * page);
    // With huge pages asked for, an array of 2 MiB or more starts on a 2 MiB boundary, so that
    // all of it can be backed by huge pages and not only the aligned middle.
    const std::size_t huge = 2u << 20;
    const std::size_t align = policy_.hugepages == HugePages::thp && len >= huge ? huge : page;
    const std::size_t mapped = len + 2 * page + (align - page);
    void* m = mmap(nullptr, mapped, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (m == MAP_FAILED)
        throw std::runtime_error("cannot map " + format_bytes(len) + " for array '" + name +
                                 "': " + std::strerror(errno));
    char* const first = static_cast<char*>(m);
    char* const p = first + ((reinterpret_cast<std::uintptr_t>(first + page) + align - 1) / align * align -
                             reinterpret_cast<std::uintptr_t>(first));
    blocks_.push_back({name, p, len, m, mapped});
    // Guards before and after: no access, and a mapping of their own that separates the array's.
    if (mprotect(first, static_cast<std::size_t>(p - first), PROT_NONE) != 0 ||
        mprotect(p + len, mapped - static_cast<std::size_t>(p - first) - len, PROT_NONE) != 0)
        throw std::runtime_error("cannot set up the guard pages of array '" + name +
                                 "': mprotect: " + std::strerror(errno));
    if (policy_.hugepages != HugePages::system &&
        madvise(p, len, policy_.hugepages == HugePages::thp ? MADV_HUGEPAGE : MADV_NOHUGEPAGE) != 0)
        throw std::runtime_error(
            "cannot advise " + std::string(policy_.hugepages == HugePages::thp ? "MADV_HUGEPAGE" : "MADV_NOHUGEPAGE") +
            " for array '" + name + "': madvise: " + std::strerror(errno));
    if (policy_.kind == PlacementKind::local) return p;
    // The policy is set on the still-untouched range, so the first touch obeys it. mbind is
    // called directly (not through libnuma's helpers, which only print a failure) so that a
    // binding that did not take stops the run instead of mislabelling its result.
    const bool bind = policy_.kind != PlacementKind::interleave;
    std::vector<unsigned long> mask(16, 0);  // room for 1024 nodes
    for (int n : bind ? std::vector<int>{policy_.node} : policy_.nodes) {
        if (n < 0 || n >= static_cast<int>(mask.size() * 64))
            throw std::runtime_error("NUMA node " + std::to_string(n) + " out of range");
        mask[static_cast<std::size_t>(n) / 64] |= 1UL << (n % 64);
    }
    // maxnode is one more than the bits to read: the kernel reads maxnode - 1 of them.
    if (mbind(p, len, bind ? MPOL_BIND : MPOL_INTERLEAVE, mask.data(), mask.size() * 64 + 1, 0) != 0)
        throw std::runtime_error("cannot bind array '" + name + "' (" + format_bytes(len) + ") to " +
                                 (bind ? "node " + std::to_string(policy_.node) : std::string("the interleave nodes")) +
                                 ": mbind: " + std::strerror(errno));
    return p;
}

std::vector<ArrayPlacement> Arena::observe() const {
    const std::size_t page = static_cast<std::size_t>(sysconf(_SC_PAGESIZE));
    std::vector<ArrayPlacement> out;
    std::string smaps;
    {
        std::ifstream in("/proc/self/smaps");
        smaps.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    }
    constexpr std::size_t chunk = 4096;
    std::vector<void*> pages(chunk);
    std::vector<int> status(chunk);
    for (const auto& b : blocks_) {
        ArrayPlacement a;
        a.name = b.name;
        a.bytes = b.bytes;
        a.pages = b.bytes / page;
        for (std::size_t first = 0; first < a.pages; first += chunk) {
            std::size_t n = std::min(chunk, a.pages - first);
            for (std::size_t k = 0; k < n; ++k) pages[k] = static_cast<char*>(b.ptr) + (first + k) * page;
            // nodes == nullptr: move nothing, only report each page's node in `status`.
            if (move_pages(0, n, pages.data(), nullptr, status.data(), 0) != 0) {
                a.error = std::string("move_pages: ") + std::strerror(errno);
                a.pages_not_present += n;
                continue;
            }
            for (std::size_t k = 0; k < n; ++k) {
                if (status[k] >= 0)
                    a.pages_per_node[status[k]] += 1;
                else
                    a.pages_not_present += 1;
            }
        }
        const auto start = reinterpret_cast<std::uintptr_t>(b.ptr);
        a.anon_huge_bytes = anon_huge_bytes_in_smaps(smaps, start, start + b.bytes);
        if (!a.anon_huge_bytes)
            a.huge_error = smaps.empty() ? "/proc/self/smaps is not readable"
                                         : "the array's mapping has no AnonHugePages line in /proc/self/smaps";
        out.push_back(std::move(a));
    }
    return out;
}

nlohmann::json to_json(const ArrayPlacement& a) {
    nlohmann::json nodes = nlohmann::json::object();
    for (const auto& [node, count] : a.pages_per_node) nodes[std::to_string(node)] = count;
    nlohmann::json j = {{"array", a.name},
                        {"bytes", a.bytes},
                        {"pages", a.pages},
                        {"pages_per_node", nodes},
                        {"pages_not_present", a.pages_not_present}};
    if (!a.error.empty()) j["error"] = a.error;
    if (a.anon_huge_bytes)
        j["anon_huge_bytes"] = *a.anon_huge_bytes;
    else if (!a.huge_error.empty())
        j["huge_error"] = a.huge_error;
    return j;
}

std::optional<std::uint64_t> anon_huge_bytes_in_smaps(const std::string& smaps, std::uintptr_t start,
                                                      std::uintptr_t end) {
    std::istringstream in(smaps);
    std::string line;
    bool inside = false;  // reading the fields of the mapping [start, end)
    while (std::getline(in, line)) {
        // A mapping's header: "7f12a0000000-7f12a4000000 rw-p 00000000 00:00 0 ..."; its fields
        // ("Rss:       4 kB") start with a capital letter and a colon.
        const auto dash = line.find('-'), space = line.find(' ');
        const bool header = dash != std::string::npos && space != std::string::npos && dash < space &&
                            line.find(':') > space && std::isxdigit(static_cast<unsigned char>(line[0]));
        if (header) {
            if (inside) return std::nullopt;  // the mapping ended without the line
            try {
                inside = std::stoull(line.substr(0, dash), nullptr, 16) == start &&
                         std::stoull(line.substr(dash + 1, space - dash - 1), nullptr, 16) == end;
            } catch (const std::exception&) {
                inside = false;
            }
            continue;
        }
        if (inside && line.rfind("AnonHugePages:", 0) == 0) {
            std::istringstream field(line.substr(14));
            std::uint64_t kb = 0;
            std::string unit;
            if (field >> kb >> unit && unit == "kB") return kb * 1024;
            return std::nullopt;
        }
    }
    return std::nullopt;
}

namespace {

// What an address-space limit (ulimit -v, RLIMIT_AS) still lets this process map: the limit less
// what is mapped now. Beyond it an allocation fails though the machine has memory to spare.
std::uint64_t address_space_left() {
    rlimit lim{};
    if (getrlimit(RLIMIT_AS, &lim) != 0 || lim.rlim_cur == RLIM_INFINITY)
        return std::numeric_limits<std::uint64_t>::max();
    std::ifstream status("/proc/self/status");
    std::string line;
    std::uint64_t mapped = 0;
    while (std::getline(status, line))
        if (line.rfind("VmSize:", 0) == 0) mapped = std::strtoull(line.c_str() + 7, nullptr, 10) * 1024;
    const auto limit = static_cast<std::uint64_t>(lim.rlim_cur);
    return limit > mapped ? limit - mapped : 0;
}

std::uint64_t memory_left(const MemoryPolicy& policy) {
    if ((policy.kind == PlacementKind::node || policy.kind == PlacementKind::remote) && numa_available() >= 0) {
        long long free_bytes = 0;
        if (numa_node_size64(policy.node, &free_bytes) >= 0 && free_bytes >= 0)
            return static_cast<std::uint64_t>(free_bytes);
        return std::numeric_limits<std::uint64_t>::max();  // unknown: let the allocation decide
    }
    std::ifstream meminfo("/proc/meminfo");
    std::string key;
    std::uint64_t kb = 0;
    std::string unit;
    while (meminfo >> key >> kb >> unit)
        if (key == "MemAvailable:") return kb * 1024;
    return std::numeric_limits<std::uint64_t>::max();
}

}  // namespace

std::uint64_t available_memory_bytes(const MemoryPolicy& policy) {
    return std::min(memory_left(policy), address_space_left());
}

}  // namespace suite
