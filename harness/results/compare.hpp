#pragma once
// `suite compare A.json B.json [...]`: the points that the files have in common, side by side,
// each file's best and median and its ratio to the first file, a geometric mean per kernel (and
// per cache role where points met by role: compare_match.hpp), and before that the differences
// of context that change what a benchmark measures (compare_context.hpp).
#include <string>
#include <vector>

#include "harness/results/result_file.hpp"

namespace suite {

// The comparison as text (markdown = a Markdown document for a review or CI comment).
// Throws InputError when the files differ in schema_version or have no point in common, and,
// unless `force`, when they differ both as machines and in their build or settings (naming the
// settings), or when one lacks a cache role another has. Points are matched by role or by their key (matching_key: in
// MPI runs rank with rank, aggregate with aggregate, and a plain point with the aggregate of a run of one rank); points
// run on all of each machine's CPUs also match each other whatever the counts. With files of different process counts
// and nothing in common, the error says so. For one MPI file: compare_hosts.hpp.
std::string render_comparison(const std::vector<ResultFile>& files, bool markdown, bool force = false);
}  // namespace suite
