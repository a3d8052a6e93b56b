#pragma once
// The variants --stores picks, one table: the kernels that have a store variant list its name
// among their variants; --stores, its help and `suite list` read the names and help lines here.
#include <string>

#include "harness/common/choice_table.hpp"

namespace suite {

struct StoreBehaviour {
    bool plain = false;  // "default": the kernel's ordinary stores, no variant of its own
};

// default, nt (non-temporal stores), rep (the x86 string instructions rep movsb / rep stosq,
// which a CPU with fast strings (ERMS) runs in whole lines, as glibc's memcpy and memset do).
const ChoiceTable<StoreBehaviour>& store_variants();

}  // namespace suite
