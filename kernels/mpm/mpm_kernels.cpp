// mpm-p2g, mpm-g2p, mpm-step: the explicit MPM of mpm.hpp on one of `suite mpm`'s cases (--case:
// the elastic dam collapse, the default; the dam break, a fluid that flows and mixes; the
// settling column), as suite mpm runs it (mixed integration), --ppe particles per element, the
// grid in the point's --ordering, after --warm-steps untimed steps (default 5) that follow the
// point's reordering schedule, so that a point can be timed in the mixed state of a flow.
// One repetition:
//   mpm-p2g   nodes zeroed; for p, corner i of elem[p]:
//               m_n += w_i m_p;  p_n += w_i m_p v_p;  f_n += w_i m_p g - V_p σ_p ∇N_i
//             --strategy: serial, atomic, colour, partition (particles sorted by element)
//   mpm-g2p   for p: v_p += dt Σ_i w_i f_n / m_n;  x_p += dt Σ_i w_i p_n / m_n
//             --particles: seeded, shuffled, sorted, dynamic
//   mpm-step  K = --sort-every whole steps (locate, P2G, grid, G2P, velocity scatter, stress),
//             each followed by the reordering that falls due; under --sort-every=auto (the
//             default) 20 steps, reordering whenever the order has decayed (mpm.hpp, OrderTracker);
//             --particles: seeded, shuffled, sorted, dynamic; the scatters serial on one thread,
//             partition on more
// Rates count particles (particle-steps for mpm-step). Bytes follow the STREAM convention for
// the particle arrays only: what the nodes cost depends on the order, which is the question.
// Flops likewise count the particle loops only (the loops over nodes: see step_flops).
// The particle arrays, the nodes and the element volume sums are the point's arena's (mpm.hpp,
// State), so --placement applies to them and the record's placement.arrays lists them; the grid
// stays the state's own memory.
#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <string>

#include "harness/common/text.hpp"
#include "harness/common/units.hpp"
#include "harness/kernel/kernel.hpp"
#include "kernels/mesh/mesh_spec.hpp"
#include "kernels/mpm/choices.hpp"
#include "kernels/mpm/kernel_checks.hpp"
#include "kernels/mpm/mpm.hpp"

namespace suite::mpm {

namespace {

enum class Phase { p2g, g2p, step };

// Bytes of particle arrays per particle, by pass (mpm.hpp's loops; w is 32 B, stress 48 B).
constexpr double p2g_bytes = 32 + 4 + 8 + 8 + 24 + 48     // w, elem, m, V, v, σ
                             + 4 + 8;                     // mixed integration's element volume sums: elem, V
constexpr double g2p_bytes = 4 + 32 + 24 + 24 + 24 + 24;  // elem, w, v, x read; v, x written
constexpr double step_bytes = p2g_bytes + g2p_bytes + (32 + 8 + 24 + 4)  // the velocity scatter
                              + (4 + 56 + 56)                            // stress and volume, read and written
                              + (24 + 4 + 32 + 4);                       // locate: x, elem read; w, elem written
// Flops per particle, by pass, counted as the loops are written (a multiply-add as two, a division
// as one; index arithmetic, comparisons, std::max and std::clamp, and the scatters' atomics, colours
// and partition slots not counted).
// P2G (step.cpp p2g, sum_element_volumes; scatter.hpp volume_scale, scatter):
//   the element volume sum Σ V_p: 1;
//   the mixed volume scale: det of the gradients 14 (3 x (2 mul + sub), 3 mul, 2 add), 1 / (6 |det| Σ V)
//     3, V_p times it 1 (counted for every particle: one in an element at the material's surface
//     skips the 17 before that multiply);
//   per corner: w m 1, w m v 3, each force component w m g - V (σ ∇N) 8 (mul; 3 mul, 2 add; mul; sub);
//   the scatter's additions: 7 into each corner.
constexpr double p2g_flops = 1 + (14 + 3 + 1) + 4 * (1 + 3 + 3 * 8) + 4 * 7;  // 159
// G2P (step.cpp g2p): per corner w / m_n 1, a += w f and v += w p 3 x 4; per axis v += dt a and
// x + dt v 4.
constexpr double g2p_flops = 4 * (1 + 3 * 4) + 3 * 4;  // 64
// One step per particle (step.cpp step, locate.cpp locate, grid.cpp next_step): P2G, G2P, then
//   velocity scatter: w m v 2 for each of 3 components, 3 additions, into 4 corners: 36;
//   ∇v: 4 corners x 9 multiply-adds 72; Δε and Δω: 9 x 2 x (mul, add or sub, mul) 54; tr 2; V *= 1 + tr 2;
//   elastic σ: Δω σ - σ Δω 9 x 3 x 4, σ + 2μ Δε + λ tr + that 9 x 5 + 3 (λ tr on the diagonal),
//     symmetrised 3 x 2: 162;
//   fluid σ: J 2, p 3, tr / 3 and 2 η / dt 3, diagonal 3 x 3, off-diagonal 3: 20; and before the
//     step, |v|² for dt 5;
//   locate: the shape functions of one element 4 x 6 (the walk's steps into a new element add 24
//     each), clipped and renormalised 4 add + 4 div: 32.
// Not counted, as the bytes leave them out: the loops over nodes (update_grid 18 and the nodal
// velocity 3 per node with mass; a box grid has about 1 / (6 ppe) such nodes a particle, under one
// flop a particle at ppe 4) and the reordering after the K steps (locate again: 32 a particle
// sorted, 64 dynamic), so that a step's count stays one number a particle for every variant.
constexpr double step_flops(Material::Model model) {
    constexpr double velocity_and_strain = 36 + 72 + 54 + 2 + 2;
    constexpr double locate = 4 * 6 + 4 + 4;
    return model == Material::Model::fluid
               ? 5 + p2g_flops + g2p_flops + velocity_and_strain + 20 + locate
               : p2g_flops + g2p_flops + velocity_and_strain + 162 + locate;  // fluid 446, elastic 583
}
constexpr double nan = std::numeric_limits<double>::quiet_NaN();  // untimed steps before the first repetition:
                                                                  // velocities and stresses not zero

class MpmKernel final : public Kernel {
public:
    MpmKernel(const KernelConfig& cfg, Phase phase) : cfg_(cfg), phase_(phase) {
        case_ = cfg.choice("case");
        setup_.settings = cases().at(case_).what.settings;
        warm_steps_ = static_cast<long>(cfg.param("warm-steps"));
        setup_.mesh = cfg.mesh.empty() ? box_spec_for(cfg.size) : cfg.mesh;
        setup_.ordering = cfg.access.name;
        setup_.particles = phase == Phase::p2g ? "sorted" : cfg.variant;
        setup_.sort_every = phase == Phase::step ? sort_every_of(cfg) : 0;
        setup_.sort_threshold = particle_orders().at(setup_.particles).what.sort_threshold;
        setup_.settings.per_element = static_cast<int>(cfg.param("ppe"));
        setup_.strategy = phase == Phase::p2g ? parse_strategy(cfg.variant)
                                              : (cfg.threads > 1 ? Strategy::partition : Strategy::serial);
        setup_.threads = cfg.threads;
        setup_.seed = cfg.seed;
    }

    void setup(Arena& arena) override {
        // The particle arrays, the nodes and the element volume sums in the point's arena, first
        // touched by the threads that compute on them (mpm.hpp, State); the reorderings write back
        // into the same pages.
        st_ = std::make_unique<State>(build(setup_, &arena));
        // The untimed steps reach a state with motion and stress (a long warm-up: the mixed state
        // of a flow), under the point's reordering schedule, as a simulation would; the timing
        // then starts right after a reordering, as every later repetition does.
        for (long k = 0; k < warm_steps_; ++k) advance(*st_, setup_);
        if (particle_orders().at(setup_.particles).what.sorts) reorder(*st_, setup_, ReorderCause::start);
        reorderings_start_ = st_->order.count;
        // The particle arrays kept their pages through the reorderings (each thread's block is
        // the same range of particles); the nodes' split follows node_hi, which the warm-up and a
        // renumbering moved: a fresh first touch for the split the timed steps start with.
        touch_nodes(*st_, true);
        if (phase_ == Phase::step) equivalence_ = check_equivalence(setup_);
        if (phase_ == Phase::g2p) {
            p2g(*st_);
            update_grid(*st_);
            start_ = std::make_unique<State>(*st_);
        }
        mass_ = mass_by_id(st_->particles);
        calls_ = 0;
        // Poisoned, so that verify() judges what the timed runs left, not the warm-up's nodes.
        if (phase_ == Phase::p2g)
            std::fill(st_->nodes.begin(), st_->nodes.end(), NodeState{nan, {nan, nan, nan}, {nan, nan, nan}, 0});
    }

    void run(int calls) override {
        State& st = *st_;
        for (int c = 0; c < calls; ++c) {
            switch (phase_) {
                case Phase::p2g:
                    p2g(st);
                    break;
                case Phase::g2p:
                    g2p(st);
                    break;
                case Phase::step:
                    for (int k = 0; k < steps_per_call(); ++k) advance(st, setup_);
                    break;
            }
        }
        calls_ += calls;
    }

    Verification verify() override {
        std::string failed, what;
        if (calls_ == 0)
            failed = "no repetition ran";
        else
            switch (phase_) {
                case Phase::p2g:
                    what =
                        "nodal m, p, f equal a serial P2G of the same particles (1e-12 of the largest), Σ m_n = Σ m_p";
                    failed = check_p2g_against_serial(*st_);
                    break;
                case Phase::g2p:
                    what = "velocities and positions equal a serial replay of the " + std::to_string(calls_) +
                           " calls exactly";
                    failed = check_g2p_replay(*start_, *st_, calls_);
                    break;
                case Phase::step:
                    what = "the first " + std::to_string(equivalence_steps) +
                           " steps equal natural order, serial, seeded (1e-10); after " + std::to_string(st_->steps) +
                           " steps: finite, inside the box, located, mass exact, Σ m_n = Σ m_p" +
                           reorderings_text(*st_, setup_, reorderings_start_);
                    failed = equivalence_;
                    if (failed.empty()) failed = check_state(*st_, mass_);
                    break;
            }
        Verification v;
        v.passed = failed.empty();
        v.detail = describe() + (failed.empty() ? what : "FAILED: " + failed);
        return v;
    }

    std::vector<Fact> facts() const override {
        // Nodes with mass in the last P2G (verify() leaves one): the grid side of the work, so that
        // nodes/s = units/s x active-nodes / particles.
        std::uint64_t active = 0;
        for (std::uint32_t n = 0; n < st_->node_hi; ++n) active += st_->nodes[n].m > 0 ? 1 : 0;
        std::vector<Fact> f{{"particles", static_cast<double>(st_->particles.size()), ""},
                            {"active-nodes", static_cast<double>(active), "nodes"},
                            {"dt", st_->dt, "s"}};
        if (phase_ == Phase::step) {
            f.push_back({"simulated", st_->time, "s"});
            f.push_back({"clamped", static_cast<double>(st_->clamped), "particle positions"});
            if (particle_orders().at(setup_.particles).what.sorts)
                for (Fact& r : reordering_facts(*st_, setup_, reorderings_start_)) f.push_back(std::move(r));
        }
        if (phase_ == Phase::p2g) {
            const Strategy s = st_->plan.strategy;
            f.push_back({"synchronised",
                         static_cast<double>(s == Strategy::atomic ? atomic_conflicts(*st_) : st_->plan.synchronised),
                         "node updates"});
            if (s == Strategy::colour) f.push_back({"colours", static_cast<double>(st_->plan.colours()), "barriers"});
            if (s == Strategy::partition)
                f.push_back({"shared-nodes", static_cast<double>(st_->plan.shared_nodes), "nodes"});
        }
        return f;
    }

    Work work() const override {
        const double np = static_cast<double>(st_->particles.size());
        Work w;
        switch (phase_) {
            case Phase::p2g:
                w.units = np, w.stream_bytes = np * p2g_bytes, w.flops = np * p2g_flops;
                break;
            case Phase::g2p:
                w.units = np, w.stream_bytes = np * g2p_bytes, w.flops = np * g2p_flops;
                break;
            case Phase::step:
                w.units = np * steps_per_call(), w.stream_bytes = w.units * step_bytes,
                w.flops = w.units * step_flops(st_->settings.material.model);
                break;
        }
        w.hardware_bytes = w.stream_bytes;
        w.footprint_bytes = footprint(*st_);
        return w;
    }

private:
    int steps_per_call() const { return steps_per_repetition(setup_.sort_every, auto_steps); }
    static constexpr int auto_steps = 20;
    std::string describe() const {
        return case_ + " on box grid " + setup_.mesh + " (" + std::to_string(st_->grid.elements()) + " tetrahedra, " +
               std::to_string(st_->particles.size()) + " particles, after " + std::to_string(warm_steps_) +
               " untimed steps), " + setup_.ordering + ", particles " + setup_.particles + ", " +
               strategy_name(st_->plan.strategy) + ": ";
    }

    KernelConfig cfg_;
    Phase phase_;
    std::string case_;
    long warm_steps_ = 5;
    Setup setup_;
    std::unique_ptr<State> st_, start_;
    std::string equivalence_;
    double mass_ = 0;
    long calls_ = 0;
    std::uint64_t reorderings_start_ = 0;  // the tracker's count where the timing starts
};

void add(const std::string& name, Phase phase, const std::string& formula, const std::string& notes) {
    KernelEntry e = mpm_entry(name, formula, phase == Phase::step ? "particle-step" : "particle", phase == Phase::p2g,
                              phase == Phase::step);
    e.info.read_bytes_per_unit = phase == Phase::p2g ? p2g_bytes : phase == Phase::g2p ? 4 + 32 + 24 + 24 : step_bytes;
    if (phase == Phase::g2p) e.info.write_bytes_per_unit = 24 + 24;  // v and x: g2p_bytes is the two together
    // A step's: the default case's (dam-collapse; column's too, both elastic); dam-break's fluid
    // step counts step_flops(fluid), in its records' work.
    e.info.flops_per_unit = phase == Phase::p2g   ? p2g_flops
                            : phase == Phase::g2p ? g2p_flops
                                                  : step_flops(Material::Model::elastic);
    e.info.notes = notes;
    e.default_meshes = {"box:24,24,24"};
    e.make = [phase](const KernelConfig& cfg) { return std::make_unique<MpmKernel>(cfg, phase); };
    e.validate = [name](const KernelConfig& cfg) {
        validate_mpm(cfg, name, cfg.mesh.empty() ? box_spec_for(cfg.size) : cfg.mesh);
    };
    register_kernel(std::move(e));
}

const bool registered = [] {
    add("mpm-p2g", Phase::p2g, "m_n += w m_p; p_n += w m_p v_p; f_n += w m_p g - V_p σ_p ∇N_i",
        "MPM particle-to-grid scatter; --strategy=" + join(strategies().names(), ",") +
            " (default all; serial on one thread)");
    add("mpm-g2p", Phase::g2p, "v_p += dt Σ w f_n / m_n; x_p += dt Σ w p_n / m_n",
        "MPM grid-to-particle update; --particles=" + join(particle_orders().names(), ",") + " (default all)");
    add("mpm-step", Phase::step,
        "K whole USL steps (locate, P2G, grid, G2P, velocity, stress), each with the reordering due",
        "explicit MPM (--case: " + cases().accepted() +
            "), a repetition K = --sort-every steps, or 20 under --sort-every=auto (the default: a reordering "
            "whenever the order has decayed); --particles=" +
            join(particle_orders().names(), ",") + " (default all)");
    return true;
}();

}  // namespace

}  // namespace suite::mpm
