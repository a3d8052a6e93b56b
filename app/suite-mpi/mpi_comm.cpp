#include "app/suite-mpi/mpi_comm.hpp"

#include <mpi.h>

#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

namespace suite {

namespace {

int as_count(std::int64_t n, const char* what) {
    if (n < 0 || n > std::numeric_limits<int>::max())
        throw std::runtime_error(std::string("MPI: ") + what + " of " + std::to_string(n) +
                                 " values does not fit one message");
    return static_cast<int>(n);
}

}  // namespace

MpiComm::MpiComm() {
    MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
    MPI_Comm_size(MPI_COMM_WORLD, &size_);
}

void MpiComm::barrier() const { MPI_Barrier(MPI_COMM_WORLD); }

void MpiComm::sum(std::span<double> values) const {
    if (size_ == 1 || values.empty()) return;
    const int n = as_count(static_cast<std::int64_t>(values.size()), "a sum");
    std::vector<double> all(static_cast<std::size_t>(n) * static_cast<std::size_t>(size_));
    MPI_Allgather(values.data(), n, MPI_DOUBLE, all.data(), n, MPI_DOUBLE, MPI_COMM_WORLD);
    for (int i = 0; i < n; ++i) {
        double s = 0;
        for (int r = 0; r < size_; ++r) s += all[static_cast<std::size_t>(r) * n + i];
        values[i] = s;
    }
}

std::int64_t MpiComm::max(std::int64_t value) const {
    long long in = value, out = 0;
    MPI_Allreduce(&in, &out, 1, MPI_LONG_LONG, MPI_MAX, MPI_COMM_WORLD);
    return out;
}

void MpiComm::exchange(std::span<const HaloPeer> peers) const {
    std::vector<MPI_Request> requests;
    requests.reserve(2 * peers.size());
    constexpr int tag = 16;
    for (const HaloPeer& p : peers)
        if (p.recv_count > 0) {
            requests.emplace_back();
            MPI_Irecv(p.recv, as_count(p.recv_count, "a halo"), MPI_DOUBLE, p.rank, tag, MPI_COMM_WORLD,
                      &requests.back());
        }
    for (const HaloPeer& p : peers)
        if (p.send_count > 0) {
            requests.emplace_back();
            MPI_Isend(p.send, as_count(p.send_count, "a halo"), MPI_DOUBLE, p.rank, tag, MPI_COMM_WORLD,
                      &requests.back());
        }
    MPI_Waitall(static_cast<int>(requests.size()), requests.data(), MPI_STATUSES_IGNORE);
}

}  // namespace suite
