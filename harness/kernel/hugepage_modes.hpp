#pragma once
// --hugepages's choices, one table (harness/common/choice_table.hpp): parsing
// (machine/placement.hpp's parse_hugepages), --help and the name a record keeps (hugepages_name)
// all read it.
#include "harness/common/choice_table.hpp"
#include "harness/kernel/arena.hpp"

namespace suite {

const ChoiceTable<HugePages>& hugepage_modes();

}  // namespace suite
