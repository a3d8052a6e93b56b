#pragma once
// Splitting and joining text: the comma lists of the command line, the lines of a report.
#include <string>
#include <string_view>
#include <vector>

namespace suite {

// The parts of `text` between each `sep` (empty parts kept: "a,,b" is {"a", "", "b"}).
std::vector<std::string> split(std::string_view text, char sep);
// The parts with `sep` between them.
std::string join(const std::vector<std::string>& parts, std::string_view sep);

}  // namespace suite
