#pragma once
// "Did you mean ...?": the nearest of the names a user could have meant.
#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

namespace suite {

// Levenshtein distance, for "did you mean ...?" suggestions.
std::size_t edit_distance(std::string_view a, std::string_view b);
// The candidate nearest to `word`, or "" when none is reasonably close.
std::string nearest(std::string_view word, const std::vector<std::string>& candidates);

}  // namespace suite
