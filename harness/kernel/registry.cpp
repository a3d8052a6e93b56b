#include <algorithm>
#include <stdexcept>
#include <string>

#include "harness/kernel/kernel.hpp"

namespace suite {

namespace {
// A function-local static: registration runs during static initialisation of other files,
// whose order relative to this one is unspecified.
std::vector<KernelEntry>& table() {
    static std::vector<KernelEntry> entries;
    return entries;
}
}  // namespace

bool register_kernel(KernelEntry entry) {
    if (find_kernel(entry.info.name)) throw std::logic_error("kernel registered twice: " + entry.info.name);
    auto& t = table();
    t.push_back(std::move(entry));
    std::sort(t.begin(), t.end(), [](const KernelEntry& a, const KernelEntry& b) {
        return a.info.group != b.info.group ? a.info.group < b.info.group : a.info.name < b.info.name;
    });
    return true;
}

const std::vector<KernelEntry>& kernels() { return table(); }

const KernelEntry* find_kernel(const std::string& name) {
    for (const auto& e : table())
        if (e.info.name == name) return &e;
    return nullptr;
}

std::vector<std::string> kernel_names() {
    std::vector<std::string> names;
    for (const auto& e : table()) names.push_back(e.info.name);
    return names;
}

void require_team_size(int got, int asked) {
    if (got != asked)
        throw std::runtime_error("OpenMP gave " + std::to_string(got) + " thread(s) where " + std::to_string(asked) +
                                 " were asked for (is OMP_THREAD_LIMIT set?)");
}

}  // namespace suite
