#include "harness/results/compare_match.hpp"

#include <algorithm>

#include "harness/results/context_fields.hpp"

namespace suite {

namespace {

// A key without the thread count, for points on every CPU of machines of different counts.
PointKey all_threads_key(PointKey k) {
    k.threads = -1;
    return k;
}

// A key without the size, for points of the default sweep sized from the same cache.
PointKey role_key(PointKey k, const std::string& role) {
    k.size = 0;
    k.size_kind = "role " + role;
    return k;
}

std::string tag(std::size_t i) { return "[" + std::to_string(i + 1) + "]"; }

}  // namespace

PointMatcher::PointMatcher(const std::vector<ResultFile>& files)
    : files_(files), by_key_(files.size()), by_role_(files.size()) {
    for (std::size_t f = 0; f < files.size(); ++f)
        for (const auto& p : files[f].points) {
            const PointKey key = matching_key(p.key);
            by_key_[f].emplace(key, &p);
            if (!p.role.name.empty()) by_role_[f].emplace(role_key(key, p.role.name), &p);
            if (!on_all_threads(f, p)) continue;
            by_key_[f].emplace(all_threads_key(key), &p);
            if (!p.role.name.empty()) by_role_[f].emplace(all_threads_key(role_key(key, p.role.name)), &p);
        }
}

// A point run on every CPU the machine has ("--threads=all", or the same count given by
// number): two machines' "all threads" points are one comparable point whatever their counts.
// In an MPI run a rank's machine is its host, and the aggregate's is every host together.
bool PointMatcher::on_all_threads(std::size_t f, const LoadedPoint& p) const {
    const ResultFile& file = files_[f];
    if (p.key.threads <= 1) return false;
    if (file.mpi && p.mpi.scope != RankOrigin::Scope::none) {
        long pus = 0;
        for (const auto& h : file.mpi->hosts)
            if (p.mpi.scope == RankOrigin::Scope::aggregate || h.host == p.mpi.host) pus += h.pus;
        return pus == p.key.threads;
    }
    return context_text(file.context, "pus") == std::to_string(p.key.threads);
}

Match PointMatcher::match(std::size_t f, const LoadedPoint& p) const {
    const PointKey key = matching_key(p.key);
    const bool all = on_all_threads(0, p);
    auto find = [](const std::map<PointKey, const LoadedPoint*>& index, const PointKey& k) -> const LoadedPoint* {
        auto it = index.find(k);
        return it == index.end() ? nullptr : it->second;
    };
    if (!p.role.name.empty()) {
        const PointKey rk = role_key(key, p.role.name);
        const LoadedPoint* q = find(by_role_[f], rk);
        if (!q && all) q = find(by_role_[f], all_threads_key(rk));
        if (q) return {q, q->key.size != p.key.size};
    }
    // By size; but a point of another role at the same size is another cache's point, not this one's.
    auto same_size = [&](const LoadedPoint* q) {
        return q && (p.role.name.empty() || q->role.name.empty() || q->role.name == p.role.name);
    };
    if (const LoadedPoint* q = find(by_key_[f], key); same_size(q)) return {q, false};
    if (all)
        if (const LoadedPoint* q = find(by_key_[f], all_threads_key(key)); same_size(q)) return {q, false};
    return {};
}

std::vector<std::string> roles_of(const ResultFile& f) {
    std::vector<std::string> out;
    for (const auto& p : f.points)
        if (!p.role.name.empty() && std::find(out.begin(), out.end(), p.role.name) == out.end())
            out.push_back(p.role.name);
    return out;
}

void check_roles(const std::vector<ResultFile>& files, bool force) {
    if (force) return;
    for (std::size_t a = 0; a < files.size(); ++a)
        for (std::size_t b = 0; b < files.size(); ++b) {
            const auto ra = roles_of(files[a]), rb = roles_of(files[b]);
            if (a == b || ra.empty() || rb.empty()) continue;
            for (const auto& role : ra)
                if (std::find(rb.begin(), rb.end(), role) == rb.end())
                    throw InputError(
                        tag(b) + " " + files[b].path + " has no " + role + " point, which " + tag(a) + " " +
                        files[a].path + " has (" +
                        (role == "DRAM" || role.substr(0, 2) == "L1" || role.substr(0, 2) == "L2"
                             ? std::string("a default sweep has it: was that file run with --kernel or --threads?")
                             : role + " is measured only where --probe-caches found the last level") +
                        "); run both the same way, or pass --force to compare the roles they share");
        }
}

}  // namespace suite
