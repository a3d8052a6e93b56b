#pragma once
// The part of `suite compare` before its table: the context fields on which the files differ,
// each said to be of the machine, of the build or settings the user chose, or informational;
// and the refusal of files that differ both as machines and in the user's settings.
#include <string>
#include <vector>

#include "harness/results/result_file.hpp"

namespace suite {

// The differences as text (a table; markdown: a Markdown section). Throws InputError, unless
// `force`, when the files differ as machines and in a setting the user chose, naming both: the
// flags that differ (compiler_flags), and the other settings with each file's value.
std::string render_context_differences(const std::vector<ResultFile>& files, bool markdown, bool force);

}  // namespace suite
