#pragma once
// How the points of several result files meet in `suite compare`: by their key (matching_key);
// points of the default sweep, which carry the cache their size came from (a role: "L2/2"),
// by that role when the machines' caches give them different sizes; and points run on all of
// each machine's CPUs whatever the counts. Sizes a user gave (--sizes) meet by size only.
#include <cstddef>
#include <map>
#include <string>
#include <vector>

#include "harness/results/result_file.hpp"

namespace suite {

struct Match {
    const LoadedPoint* point = nullptr;  // none: the file has no such point
    bool by_role = false;                // met by role, their sizes differing
};

class PointMatcher {
public:
    explicit PointMatcher(const std::vector<ResultFile>& files);
    // The point of file `f` that stands where `p`, a point of the first file, stands: the same
    // role (for a point with one), else the same key among points of no other role; then the
    // same again on all of each machine's CPUs.
    Match match(std::size_t f, const LoadedPoint& p) const;
    // Whether `p` of file `f` ran on all of its machine's CPUs (with more than one).
    bool on_all_threads(std::size_t f, const LoadedPoint& p) const;

private:
    const std::vector<ResultFile>& files_;
    std::vector<std::map<PointKey, const LoadedPoint*>> by_key_, by_role_;
};

// The roles of a file's points ("L1/2", "L2/2", "L3/2", "DRAM"), in the order they first appear.
std::vector<std::string> roles_of(const ResultFile& f);

// The refusal (InputError) of files that cannot be compared by role: a role one of them has and
// another lacks, naming both files and the role. Files without roles (sizes given, older files)
// are left to meet by size. `force`: only the roles they share are compared.
void check_roles(const std::vector<ResultFile>& files, bool force);

}  // namespace suite
