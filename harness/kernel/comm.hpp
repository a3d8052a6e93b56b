#pragma once
// The processes a run spans, as a kernel and the runner see them: a rank, a size, a barrier,
// sums and maxima over the ranks, and the exchange of halo values with neighbouring ranks.
// The plain build runs on the one-process Comm below; `suite-mpi` hands every kernel an MPI
// implementation (app/suite-mpi/), so that nothing here or in a kernel includes MPI.
// A kernel that distributes its work reads KernelConfig::comm; every other kernel ignores it
// and simply runs on every rank at once (the runner starts the ranks' repetitions together).
#include <cstdint>
#include <span>
#include <stdexcept>
#include <string>

namespace suite {

// One neighbour of a halo exchange: `send_count` doubles from `send` go to `rank`, and
// `recv_count` doubles arrive from it into `recv`. Both sides must agree on the counts.
struct HaloPeer {
    int rank = -1;
    const double* send = nullptr;
    std::int64_t send_count = 0;
    double* recv = nullptr;
    std::int64_t recv_count = 0;
};

class Comm {
public:
    virtual ~Comm() = default;
    virtual int rank() const = 0;
    virtual int size() const = 0;
    // Every call below is collective: every rank calls it, in the same order.
    virtual void barrier() const = 0;
    // values[i] becomes the sum over the ranks of values[i], on every rank; the sum is taken in
    // rank order, so that every rank (and every run on the same ranks) gets the same bits.
    virtual void sum(std::span<double> values) const = 0;
    virtual std::int64_t max(std::int64_t value) const = 0;
    // Sends and receives every peer's values; returns when all have arrived. Not collective over
    // all ranks: only the peers listed take part, and each must list this rank in turn.
    virtual void exchange(std::span<const HaloPeer> peers) const = 0;
};

// A run of one process: rank 0 of 1, every collective the identity, and no peers.
class SingleProcess final : public Comm {
public:
    int rank() const override { return 0; }
    int size() const override { return 1; }
    void barrier() const override {}
    void sum(std::span<double>) const override {}
    std::int64_t max(std::int64_t value) const override { return value; }
    void exchange(std::span<const HaloPeer> peers) const override {
        if (!peers.empty()) throw std::logic_error("a halo exchange with another rank in a run of one process");
    }
};

// The process-wide one-process Comm, for configurations built without a Comm of their own.
inline const Comm& single_process() {
    static const SingleProcess one;
    return one;
}

}  // namespace suite
