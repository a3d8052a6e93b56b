#pragma once
// A Comm made of threads, for testing distributed kernels without MPI: rank r is a std::thread,
// the collectives meet at a std::barrier, and the halo exchange is point to point through
// per-pair mailboxes (a send is buffered; a receive waits for its sender), so that, as with MPI,
// only the peers of an exchange take part in it.
#include <algorithm>
#include <barrier>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <exception>
#include <functional>
#include <mutex>
#include <span>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "harness/kernel/comm.hpp"

namespace suite::testing_comm {

class ThreadWorld {
public:
    explicit ThreadWorld(int size)
        : size_(size),
          barrier_(size),
          sums_(static_cast<std::size_t>(size)),
          maxima_(static_cast<std::size_t>(size)),
          boxes_(static_cast<std::size_t>(size) * static_cast<std::size_t>(size)),
          locks_(static_cast<std::size_t>(size)),
          ready_(static_cast<std::size_t>(size)) {}
    int size() const { return size_; }

    void barrier() { barrier_.arrive_and_wait(); }

    void sum(int rank, std::span<double> values) {
        sums_[static_cast<std::size_t>(rank)].assign(values.begin(), values.end());
        barrier();
        for (std::size_t i = 0; i < values.size(); ++i) {
            double total = 0;
            for (int r = 0; r < size_; ++r) total += sums_[static_cast<std::size_t>(r)].at(i);
            values[i] = total;
        }
        barrier();  // every rank has read the slots before any is written again
    }

    std::int64_t max(int rank, std::int64_t value) {
        maxima_[static_cast<std::size_t>(rank)] = value;
        barrier();
        std::int64_t most = value;
        for (const std::int64_t v : maxima_) most = std::max(most, v);
        barrier();
        return most;
    }

    void exchange(int rank, std::span<const HaloPeer> peers) {
        for (const HaloPeer& p : peers) {
            if (p.rank < 0 || p.rank >= size_ || p.rank == rank)
                throw std::logic_error("exchange with rank " + std::to_string(p.rank));
            const std::size_t to = static_cast<std::size_t>(p.rank);
            {
                const std::lock_guard<std::mutex> hold(locks_[to]);
                box(rank, p.rank).emplace_back(p.send, p.send + p.send_count);
            }
            ready_[to].notify_all();
        }
        const std::size_t me = static_cast<std::size_t>(rank);
        for (const HaloPeer& p : peers) {
            std::unique_lock<std::mutex> hold(locks_[me]);
            auto& from = box(p.rank, rank);
            ready_[me].wait(hold, [&] { return !from.empty(); });
            const std::vector<double> got = std::move(from.front());
            from.pop_front();
            hold.unlock();
            if (static_cast<std::int64_t>(got.size()) != p.recv_count)
                throw std::logic_error("rank " + std::to_string(rank) + " expected " + std::to_string(p.recv_count) +
                                       " values from rank " + std::to_string(p.rank) + ", which sent " +
                                       std::to_string(got.size()));
            std::copy(got.begin(), got.end(), p.recv);
        }
    }

private:
    std::deque<std::vector<double>>& box(int from, int to) {
        return boxes_[static_cast<std::size_t>(from * size_ + to)];
    }

    int size_;
    std::barrier<> barrier_;
    std::vector<std::vector<double>> sums_;
    std::vector<std::int64_t> maxima_;
    std::vector<std::deque<std::vector<double>>> boxes_;  // [from * size + to], guarded by the receiver's lock
    std::vector<std::mutex> locks_;
    std::vector<std::condition_variable> ready_;
};

class ThreadComm final : public Comm {
public:
    ThreadComm(ThreadWorld& world, int rank) : world_(world), rank_(rank) {}
    int rank() const override { return rank_; }
    int size() const override { return world_.size(); }
    void barrier() const override { world_.barrier(); }
    void sum(std::span<double> values) const override { world_.sum(rank_, values); }
    std::int64_t max(std::int64_t value) const override { return world_.max(rank_, value); }
    void exchange(std::span<const HaloPeer> peers) const override { world_.exchange(rank_, peers); }

private:
    ThreadWorld& world_;
    int rank_;
};

// Runs body(comm) on `ranks` threads, one rank each, and rethrows the first exception a rank threw.
// A rank that throws leaves the others waiting at their next collective: the bodies of the tests
// throw only where every rank does.
inline void run_ranks(int ranks, const std::function<void(const Comm&)>& body) {
    ThreadWorld world(ranks);
    std::vector<std::exception_ptr> errors(static_cast<std::size_t>(ranks));
    std::vector<std::thread> threads;
    for (int r = 0; r < ranks; ++r)
        threads.emplace_back([&, r] {
            try {
                const ThreadComm comm(world, r);
                body(comm);
            } catch (...) {
                errors[static_cast<std::size_t>(r)] = std::current_exception();
            }
        });
    for (auto& t : threads) t.join();
    for (auto& e : errors)
        if (e) std::rethrow_exception(e);
}

}  // namespace suite::testing_comm
