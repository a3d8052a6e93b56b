#include "kernels/mpm/free_fall.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace suite::mpm {

FreeFall::FreeFall(const State& st, bool on) : on_(on) {
    if (!on_) return;
    const Particles& p = st.particles;
    x0_.resize(p.size()), y0_.resize(p.size()), z0_.resize(p.size());
    for (std::size_t i = 0; i < p.size(); ++i) x0_[p.id[i]] = p.x[i], y0_[p.id[i]] = p.y[i], z0_[p.id[i]] = p.z[i];
}

void FreeFall::observe(const State& st) {
    if (!on_ || landed_) return;
    // The nodes hold the step's P2G: a node on a wall with mass means the walls acted in it.
    for (std::uint32_t n = 0; n < st.node_hi; ++n)
        if (st.grid.wall[n] != 0 && st.nodes[n].m > 0) {
            landed_ = true;
            return;
        }
    const double g = st.settings.gravity[2];
    speed_ += st.dt * g;
    fall_ += st.dt * speed_;
    const Particles& p = st.particles;
    double mean = 0;
    for (std::size_t i = 0; i < p.size(); ++i) {
        const std::uint32_t id = p.id[i];
        const double d =
            std::max({std::fabs(p.x[i] - x0_[id]), std::fabs(p.y[i] - y0_[id]), std::fabs(p.z[i] - z0_[id] - fall_)});
        worst = std::max(worst, d);
        mean += p.z[i] - z0_[id];
    }
    mean /= static_cast<double>(std::max<std::size_t>(p.size(), 1));
    analytic_error = std::fabs(mean - 0.5 * g * st.time * st.time);
    analytic_bound = 0.5 * std::fabs(g) * st.time * st.dt;
    ++steps_in_flight;
}

Check free_fall_check(const FreeFall& f, const State& st, Outcome& r) {
    if (!f.on())
        return {"free fall", true,
                "not checked: the exact fall is the undamped explicit step's (--integrator=explicit, "
                "--damping=0)"};
    r.fall_steps = f.steps_in_flight;
    if (f.steps_in_flight == 0) return {"free fall", true, "not checked: a wall acted from the first step"};
    r.fall_worst = f.worst, r.fall_analytic = f.analytic_error, r.fall_bound = f.analytic_bound;
    const double tol = 1e-9 * (st.grid.hi[2] - st.grid.lo[2]);
    char b[400];
    std::snprintf(b, sizeof b,
                  "in the %llu step(s) before a wall acted every particle was within %.3g m of the explicit step's "
                  "exact fall (at most %.3g); the mean fall then differed from g t^2 / 2 by %.4g m (the step's g t dt "
                  "/ 2: %.4g m)",
                  static_cast<unsigned long long>(f.steps_in_flight), f.worst, tol, f.analytic_error, f.analytic_bound);
    return {"free fall", f.worst <= tol, b};
}

}  // namespace suite::mpm
