#include "harness/kernel/patterns.hpp"

#include <stdexcept>

#include "harness/kernel/kernel.hpp"

namespace suite {

const ChoiceTable<PatternBehaviour>& access_patterns() {
    static const ChoiceTable<PatternBehaviour> table{
        "access pattern",
        {{"sequential", "i = 0, 1, 2, ...", {Pattern::sequential, false}},
         {"random", "a seeded shuffle of 0..n-1, through an index array", {Pattern::random, false}},
         {"strided", "strided:S, every S-th element, S passes over each thread's block", {Pattern::strided, true}}}};
    return table;
}

const std::string& pattern_name(Pattern p) {
    for (const auto& c : access_patterns().all())
        if (c.what.pattern == p) return c.name;
    throw std::logic_error("a pattern without a name in access_patterns()");
}

const PatternBehaviour* find_pattern(const std::string& access_name) {
    const auto* c = access_patterns().find(access_name);
    return c ? &c->what : nullptr;
}

Pattern pattern_of(const Access& a) {
    const PatternBehaviour* p = find_pattern(a.name);
    if (!p) throw std::logic_error("'" + a.name + "' is not an access pattern");
    return p->pattern;
}

std::string Access::label() const {
    const PatternBehaviour* p = find_pattern(name);
    return p && p->takes_stride ? name + ":" + std::to_string(stride) : name;
}

}  // namespace suite
