#pragma once
// The free-fall case's check (choices.hpp, Reference::free_fall): a block at rest away from the
// walls falls under gravity alone until a wall acts. Every particle and node then moves with one
// velocity, the stress stays zero, and the explicit step (G2P: v += dt g, then x += dt v) puts
// every particle exactly at x0 + g dt² k (k + 1) / 2 after k steps of one dt: the check asks that
// to rounding (1e-9 of the box). Against the analytic x0 + g t² / 2 that is g t dt / 2 off, an
// error that shrinks with the step (and so with the grid); Outcome reports it as measured.
#include <cstdint>
#include <string>
#include <vector>

#include "kernels/mpm/mpm.hpp"
#include "kernels/mpm/simulation.hpp"

namespace suite::mpm {

class FreeFall {
public:
    // Records the starting positions by particle id; `on`: false makes every call a no-op.
    FreeFall(const State& st, bool on);
    // After each step: while no node on a wall has mass, every particle against the exact fall.
    void observe(const State& st);
    bool on() const { return on_; }
    double worst = 0;           // the largest |x - exact| over particles and steps in flight, m
    double analytic_error = 0;  // |mean z displacement - g t² / 2| at the last step in flight, m
    double analytic_bound = 0;  // g t dt / 2 there, m
    std::uint64_t steps_in_flight = 0;

private:
    bool on_ = false, landed_ = false;
    std::vector<double> x0_, y0_, z0_;
    double fall_ = 0;  // the exact discrete displacement along z so far (negative: down)
    double speed_ = 0;
};

// The check of a run's fall (at most 1e-9 of the box's height off the exact fall in every step
// in flight), its numbers put into `r`; a run that is not undamped and explicit is not checked.
Check free_fall_check(const FreeFall& f, const State& st, Outcome& r);

}  // namespace suite::mpm
