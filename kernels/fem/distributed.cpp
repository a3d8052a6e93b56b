#include "kernels/fem/distributed.hpp"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <span>
#include <stdexcept>
#include <string>
#include <utility>

#include "harness/kernel/blocks.hpp"
#include "kernels/fem/inverse_iteration.hpp"

namespace suite::fem {

HaloExchange::HaloExchange(std::int64_t owned, const std::vector<HaloLink>& links) : owned_(owned) {
    for (const HaloLink& l : links) {
        send_offset_.push_back(static_cast<std::int64_t>(send_rows_.size()));
        send_rows_.insert(send_rows_.end(), l.send.begin(), l.send.end());
        recv_offset_.push_back(l.recv_offset);
        received_ += l.recv_count;
        peers_.push_back({l.rank, nullptr, static_cast<std::int64_t>(l.send.size()), nullptr, l.recv_count});
    }
    send_buffer_.resize(send_rows_.size());
}

void HaloExchange::operator()(const Comm& comm, double* x) {
    // Gathered serially: a halo is a few hundred values a neighbour, less than a fork would cost.
    for (std::size_t j = 0; j < send_rows_.size(); ++j) send_buffer_[j] = x[send_rows_[j]];
    // The pointers are set here, not once, so that a copied HaloExchange points at its own buffer.
    for (std::size_t k = 0; k < peers_.size(); ++k) {
        peers_[k].send = send_buffer_.data() + send_offset_[k];
        peers_[k].recv = x + owned_ + recv_offset_[k];
    }
    comm.exchange(peers_);
}

DistributedSolver::DistributedSolver(const Comm& comm, const LocalSystem& system, HaloExchange halo)
    : comm_(comm), sys_(system), halo_(std::move(halo)) {}

template <class Body>
void DistributedSolver::for_blocks(Body block) const {
    const std::int64_t n = sys_.pattern.n;
#pragma omp parallel
    block(my_block(n));
}

template <std::size_t K, class Body>
std::array<double, K> DistributedSolver::sum_blocks(Body block) {
    static_assert(K <= 8, "one cache line of partial sums a thread");
    const std::int64_t n = sys_.pattern.n;
    partial_.resize(8 * static_cast<std::size_t>(std::max(1, omp_get_max_threads())));
    double* const partial = partial_.data();
    int team = 1;
#pragma omp parallel
    {
        const int t = omp_get_thread_num();
        if (t == 0) team = omp_get_num_threads();
        const std::array<double, K> mine = block(my_block(n));
        for (std::size_t j = 0; j < K; ++j) partial[8 * t + static_cast<int>(j)] = mine[j];
    }
    std::array<double, K> total{};
    for (int t = 0; t < team; ++t)
        for (std::size_t j = 0; j < K; ++j) total[j] += partial[8 * t + static_cast<int>(j)];
    comm_.sum(total);
    return total;
}

void DistributedSolver::spmv(const double* values, double* x, double* y) {
    halo_(comm_, x);
    const Pattern p = sys_.pattern;
    for_blocks([&](Block b) { spmv_rows(p, values, x, y, b.lo, b.hi); });
}

CgResult DistributedSolver::cg(const double* f, double* x, const CgVectors& v, double tol, int max_iterations) {
    double* const r = v.r;
    double* const p = v.p;
    double* const q = v.q;
    const Pattern pat = sys_.pattern;
    const double* const a = sys_.a;
    // r = f - A x, p = r.
    spmv(a, x, q);
    const auto [rr0, ff] = sum_blocks<2>([&](Block b) {
        double rr = 0, ff = 0;
        for (std::int64_t i = b.lo; i < b.hi; ++i) {
            r[i] = f[i] - q[i];
            p[i] = r[i];
            rr += r[i] * r[i];
            ff += f[i] * f[i];
        }
        return std::array<double, 2>{rr, ff};
    });
    double rr = rr0;
    CgResult out;
    const double goal = tol * tol * ff;
    while (true) {
        if (rr <= goal) {
            out.converged = true;
            break;
        }
        if (out.iterations >= max_iterations) break;
        ++out.iterations;
        // q = A p and pᵀq in one pass, once p's halo has come in.
        halo_(comm_, p);
        const double pq = sum_blocks<1>([&](Block b) {
            const std::uint32_t* const rp = pat.row_ptr;
            const std::uint32_t* const col = pat.col;
            double pq = 0;
            for (std::int64_t i = b.lo; i < b.hi; ++i) {
                double s = 0;
                for (std::uint32_t k = rp[i], end = rp[i + 1]; k < end; ++k) s += a[k] * p[col[k]];
                q[i] = s;
                pq += p[i] * s;
            }
            return std::array<double, 1>{pq};
        })[0];
        const double alpha = rr / pq;
        const double rr_new = sum_blocks<1>([&](Block b) {
            double s = 0;
            for (std::int64_t i = b.lo; i < b.hi; ++i) {
                x[i] += alpha * p[i];
                r[i] -= alpha * q[i];
                s += r[i] * r[i];
            }
            return std::array<double, 1>{s};
        })[0];
        const double beta = rr_new / rr;
        rr = rr_new;
        for_blocks([&](Block b) {
            for (std::int64_t i = b.lo; i < b.hi; ++i) p[i] = r[i] + beta * p[i];
        });
    }
    out.relative_residual = ff > 0 ? std::sqrt(rr / ff) : 0;
    return out;
}

// The ranks' solver as inverse_iteration_with sees it: the owned rows in blocks of the team,
// sums over the ranks, and each product after an exchange of its vector's halo.
struct DistributedTeam {
    DistributedSolver& s;
    const EigenVectors& v;

    template <class F>
    void each(F f) {
        s.for_blocks([&](Block b) { f(b.lo, b.hi); });
    }
    template <std::size_t K, class F>
    std::array<double, K> sum(F f) {
        return s.sum_blocks<K>([&](Block b) { return f(b.lo, b.hi); });
    }
    void products() {
        s.halo_(s.comm_, v.u);
        const Pattern pat = s.sys_.pattern;
        const double* const a = s.sys_.a;
        const double* const m = s.sys_.m;
        s.for_blocks([&](Block b) {
            spmv_rows(pat, a, v.u, v.au, b.lo, b.hi);
            spmv_rows(pat, m, v.u, v.mu, b.lo, b.hi);
        });
    }
    void mass() { s.spmv(s.sys_.m, v.u, v.f); }
    CgResult solve(double tol, int max_iterations) { return s.cg(v.f, v.u, v.cg, tol, max_iterations); }
};

EigenResult DistributedSolver::inverse_iteration(const EigenVectors& v, double tol, double cg_tol, int max_cg) {
    if (!sys_.m) throw std::logic_error("the distributed inverse iteration needs M");
    DistributedTeam team{*this, v};
    return inverse_iteration_with(team, v, tol, cg_tol, max_cg);
}

}  // namespace suite::fem
