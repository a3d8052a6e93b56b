#pragma once
// What the MPM tests share: matching particles by id, a thread-count guard, and sums that do
// not depend on the order the particles are stored in.
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "kernels/mpm/mpm.hpp"

namespace suite::mpm::testing {

// Sets the OpenMP team for a scope and gives the old size back.
class Team {
public:
    explicit Team(int n) : saved_(omp_get_max_threads()) { omp_set_num_threads(n); }
    ~Team() { omp_set_num_threads(saved_); }
    Team(const Team&) = delete;
    Team& operator=(const Team&) = delete;

private:
    int saved_;
};

// where[id] = the particle's index in p.
inline std::vector<std::size_t> index_by_id(const Particles& p) {
    std::vector<std::size_t> where(p.size());
    for (std::size_t i = 0; i < p.size(); ++i) where[p.id[i]] = i;
    return where;
}

// The largest difference of any coordinate of one particle between a and b, matched by id.
inline double max_position_difference(const Particles& a, const Particles& b) {
    const std::vector<std::size_t> where = index_by_id(b);
    double d = 0;
    for (std::size_t i = 0; i < a.size(); ++i) {
        const std::size_t j = where[a.id[i]];
        d = std::max({d, std::fabs(a.x[i] - b.x[j]), std::fabs(a.y[i] - b.y[j]), std::fabs(a.z[i] - b.z[j])});
    }
    return d;
}

// Σ m_p in id order: the same bits whatever order the particles are stored in.
inline double mass_in_id_order(const Particles& p) {
    const std::vector<std::size_t> where = index_by_id(p);
    double m = 0;
    for (std::size_t i : where) m += p.mass[i];
    return m;
}

}  // namespace suite::mpm::testing
