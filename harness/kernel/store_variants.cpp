#include "harness/kernel/store_variants.hpp"

#include "harness/kernel/kernel.hpp"

namespace suite {

const ChoiceTable<StoreBehaviour>& store_variants() {
    static const ChoiceTable<StoreBehaviour> table{
        "--stores",
        {{"default", "the kernel's ordinary stores", {.plain = true}},
         {"nt", "non-temporal stores; copy, scale, add, triad, store", {}},
         {"rep", "string instructions rep movsb / rep stosq; copy, store", {}}}};
    return table;
}

bool is_store_variant(const std::string& v) {
    const auto* c = store_variants().find(v);
    return c && !c->what.plain;
}

}  // namespace suite
