#pragma once
// The finite element solvers of solver.hpp on one rank's share of the rows (partition.hpp),
// written against the abstract Comm (harness/kernel/comm.hpp) so that nothing here includes MPI.
// A rank's vectors hold its owned rows, and, for the vectors a product reads (x, p, u), the halo
// values after them; before each product the halo is refreshed by Comm::exchange. Dot products
// are summed over the owned rows (the OpenMP team in thread order, then Comm::sum in rank order),
// so every rank takes the same decisions and a run on the same ranks and threads repeats its bits.
// The Comm is called only outside parallel regions; every member below that says "collective"
// must be called by every rank, in the same order.
//   spmv:    y = A x on the owned rows: the halo of x exchanged, then the local rows (bit for bit
//            the serial product's rows: each row keeps the global column order)
//   cg:      as cg_team: A x = f from the given x until ||f - A x|| <= tol ||f|| (recursive)
//   inverse: as inverse_iteration_team: u = 1; f = M u, A u' = f by cg from u / λ, u = u' scaled to
//            u'ᵀ M u' = 1 and Σ u > 0, λ the Rayleigh quotient, until |λ - λ_old| <= tol |λ_old|
#include <array>
#include <cstdint>
#include <vector>

#include "harness/kernel/comm.hpp"
#include "kernels/fem/csr.hpp"
#include "kernels/fem/partition.hpp"
#include "kernels/fem/solver.hpp"

namespace suite::fem {

// One rank's matrices: owned rows, local columns (owned, then `halo` received values).
struct LocalSystem {
    Pattern pattern;  // pattern.n = the owned rows
    const double* a = nullptr;
    const double* m = nullptr;  // null where no solver needs M
    std::int64_t halo = 0;
};

// The halo exchange of one rank: what it sends each neighbour (owned values gathered into a
// buffer) and where each neighbour's values land (local columns owned + recv_offset ...).
class HaloExchange {
public:
    HaloExchange() = default;
    HaloExchange(std::int64_t owned, const std::vector<HaloLink>& links);
    // Collective over the neighbours: x[owned, owned + halo) receives their owned values.
    void operator()(const Comm& comm, double* x);
    std::int64_t received() const { return received_; }  // values an exchange brings in
    std::int64_t sent() const { return static_cast<std::int64_t>(send_rows_.size()); }
    int neighbours() const { return static_cast<int>(peers_.size()); }

private:
    std::int64_t owned_ = 0, received_ = 0;
    std::vector<std::uint32_t> send_rows_;  // every link's send list, one after the other
    std::vector<double> send_buffer_;
    std::vector<std::int64_t> send_offset_, recv_offset_;  // per peer: into send_buffer_, into the halo
    std::vector<HaloPeer> peers_;                          // pointers set at each exchange
};

class DistributedSolver {
public:
    DistributedSolver(const Comm& comm, const LocalSystem& system, HaloExchange halo);

    // Collective. x has owned + halo entries (its halo is overwritten), y the owned ones.
    void spmv(const double* values, double* x, double* y);
    // Collective. x and v.p have owned + halo entries, f, v.r and v.q the owned ones.
    CgResult cg(const double* f, double* x, const CgVectors& v, double tol, int max_iterations);
    // Collective. v.u and v.cg.p have owned + halo entries, the others the owned ones.
    EigenResult inverse_iteration(const EigenVectors& v, double tol, double cg_tol, int max_cg);

    const Comm& comm() const { return comm_; }
    const LocalSystem& system() const { return sys_; }
    HaloExchange& halo() { return halo_; }

private:
    friend struct DistributedTeam;  // the inverse iteration's view of this solver (distributed.cpp)
    // Collective: `block(rows)` run by every thread of the team on its block of the owned rows; the
    // K sums it returns added up in thread order, then over the ranks (one Comm::sum).
    template <std::size_t K, class Body>
    std::array<double, K> sum_blocks(Body block);
    // `block(rows)` by every thread on its block of the owned rows; no sum, no communication.
    template <class Body>
    void for_blocks(Body block) const;

    const Comm& comm_;
    LocalSystem sys_;
    HaloExchange halo_;
    std::vector<double> partial_;  // 8 doubles (one cache line) a thread
};

}  // namespace suite::fem
