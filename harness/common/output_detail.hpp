#pragma once
// What output_file.cpp (one file) and output_dir.cpp (a directory of them) share: the checks
// of a target, the atomic replacement, the lock. Not for other folders: use output_file.hpp.
#include <sys/stat.h>

#include <string>
#include <vector>

#include "harness/common/output_file.hpp"

namespace suite::output_detail {

std::string errno_text(int err);
// The directory part of a path ("." for a bare name).
std::string parent_of(const std::string& path);
// The checks every target file passes: UsageError with `usage` (claiming), else runtime_error.
void check_target(const std::string& path, const std::string& option, const std::vector<FileIdentity>& inputs,
                  bool usage);
// Writes `content` through a temporary file beside `path`, fsynced, renamed over it.
void replace_file(const std::string& path, const std::string& content);
// Opens and locks `lock_path` for `what`; the fd. UsageError naming the holder when taken.
int take_lock(const std::string& lock_path, const std::string& what);

}  // namespace suite::output_detail
