#pragma once
// The Comm of kernel/comm.hpp over MPI_COMM_WORLD: what the runner and the distributed kernels
// use in suite-mpi. Sums are taken in rank order on every rank (an allgather, then the same loop
// everywhere), not by MPI_Allreduce, whose order of summation the standard leaves open: a
// distributed solver then takes the same decisions on every rank and in every run.
#include <span>

#include "harness/kernel/comm.hpp"

namespace suite {

class MpiComm final : public Comm {
public:
    MpiComm();
    int rank() const override { return rank_; }
    int size() const override { return size_; }
    void barrier() const override;
    void sum(std::span<double> values) const override;
    std::int64_t max(std::int64_t value) const override;
    void exchange(std::span<const HaloPeer> peers) const override;

private:
    int rank_ = 0, size_ = 1;
};

}  // namespace suite
