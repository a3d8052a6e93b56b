#include "harness/kernel/store_variants.hpp"

#include "harness/kernel/kernel.hpp"

namespace suite {

namespace {
#if defined(__x86_64__)
constexpr const char* no_rep = "";
#else
constexpr const char* no_rep =
    "rep movsb and rep stosq are x86-64 string instructions, and this build is not for x86-64";
#endif
}  // namespace

const ChoiceTable<StoreBehaviour>& store_variants() {
    static const ChoiceTable<StoreBehaviour> table{
        "--stores",
        {{"default", "the kernel's ordinary stores", {.plain = true}},
         {"nt", "non-temporal stores; copy, scale, add, triad, store", {}},
         {"rep", "string instructions rep movsb / rep stosq; copy, store; x86-64 only", {.unavailable = no_rep}}}};
    return table;
}

std::vector<std::string> usable_store_variants() {
    std::vector<std::string> out;
    for (const auto& c : store_variants().all())
        if (*c.what.unavailable == '\0') out.push_back(c.name);
    return out;
}

bool is_store_variant(const std::string& v) {
    const auto* c = store_variants().find(v);
    return c && !c->what.plain;
}

}  // namespace suite
