#pragma once
// The access patterns a kernel may walk its arrays in (--pattern), one table: their names, help
// lines, and which takes a parameter (strided:S). Kernels declare the patterns they have from it,
// the plan parses --pattern through it, and a record's access label is written from it.
#include <string>
#include <vector>

#include "harness/common/choice_table.hpp"

namespace suite {

enum class Pattern { sequential, random, strided };

struct PatternBehaviour {
    Pattern pattern = Pattern::sequential;
    bool takes_stride = false;  // named "NAME:S", S a stride in elements
};

// sequential, random, strided.
const ChoiceTable<PatternBehaviour>& access_patterns();

// The name of `p` in the table.
const std::string& pattern_name(Pattern p);

// The pattern an access names; nullptr where the name is not a pattern (a mesh ordering).
const PatternBehaviour* find_pattern(const std::string& access_name);

struct Access;
// For a kernel that walks only patterns (the plan gives it nothing else): the pattern of `a`.
Pattern pattern_of(const Access& a);

}  // namespace suite
