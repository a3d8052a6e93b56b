#pragma once
// `suite traverse`: how a loop over a mesh's elements walks it, per ordering and thread count.
// Writes, into --out=DIR, a .vtu per ordering and thread count with each element's visit index,
// owning thread and step within its thread's block; PNG snapshots of the loop at 0, 20, ...,
// 100 % (plots/traverse.py); and summary.json with the numbers that go under the figures
// (elements whose vertices are shared between threads, bandwidth, profile, vertex spread, and
// the fraction of elements sharing a key by depth). Returns the exit status.
#include <string>
#include <vector>

namespace suite::sfc {

int cmd_traverse(const std::vector<std::string>& args);

}  // namespace suite::sfc
