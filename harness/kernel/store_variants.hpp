#pragma once
// The variants --stores picks, one table: the kernels that have a store variant list its name
// among their variants; --stores, its help and `suite list` read the names and help lines here.
#include <string>
#include <vector>

#include "harness/common/choice_table.hpp"

namespace suite {

struct StoreBehaviour {
    bool plain = false;  // "default": the kernel's ordinary stores, no variant of its own
    // Why no kernel of this build has the variant (empty where they may): the plan refuses it
    // with this reason rather than with an empty list of kernels.
    const char* unavailable = "";
};

// The names --stores accepts in this build: the table's, less those unavailable here.
std::vector<std::string> usable_store_variants();

// default, nt (non-temporal stores), rep (the x86 string instructions rep movsb / rep stosq,
// which a CPU with fast strings (ERMS) runs in whole lines, as glibc's memcpy and memset do).
const ChoiceTable<StoreBehaviour>& store_variants();

}  // namespace suite
