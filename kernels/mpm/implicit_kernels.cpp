// mpm-implicit-assembly, mpm-implicit-solve, mpm-implicit-step: the implicit MPM of implicit.hpp
// on `suite mpm`'s elastic cases (--case: dam-collapse, the default, or column), the step
// --dt-multiple times the explicit stable step (default 10), the grid in the point's --ordering,
// after --warm-steps untimed implicit steps (default 5; at least one, whose Newton and CG
// iterations a step's declared bytes and flops are counted with). One repetition:
//   mpm-implicit-assembly  f_int and the tangent ∂f_int/∂Δu of the first Newton iterate (Δu = 0):
//                          for p, corners i, j of elem[p]: f_i += V_p P ∇N_i, K_ij += V_p (...);
//                          --strategy: serial, atomic, colour, partition (particles sorted)
//   mpm-implicit-solve     one Newton system K δ = r by the Jacobi-preconditioned CG, from δ = 0,
//                          on a copy of the system in the point's arena (placed as --placement
//                          says, first touched by the CG's row blocks); --particles: seeded,
//                          shuffled, sorted, dynamic (dynamic renumbers the grid, and so the
//                          system); verified against CHOLMOD's solve
//   mpm-implicit-step      K = --sort-every whole implicit steps, each with the reordering due
//                          (5 under --sort-every=auto, the default: a reordering whenever the
//                          order has decayed); --particles: seeded, shuffled, sorted, dynamic
// Rates count particles (assembly), CG iterations (solve), particle-steps (step). Bytes follow
// the STREAM convention: the particle arrays a pass reads and writes, the tangent's values
// written once and the CG's matrix and vectors each pass; flops are counted from the loops.
#include <algorithm>
#include <cmath>
#include <memory>
#include <stdexcept>
#include <string>

#include "harness/common/text.hpp"
#include "harness/common/units.hpp"
#include "harness/kernel/arena.hpp"
#include "harness/kernel/blocks.hpp"
#include "harness/kernel/kernel.hpp"
#include "kernels/fem/fem_checks.hpp"
#include "kernels/fem/sparse_libs.hpp"
#include "kernels/mpm/choices.hpp"
#include "kernels/mpm/implicit.hpp"
#include "kernels/mpm/implicit_work.hpp"
#include "kernels/mpm/kernel_checks.hpp"

namespace suite::mpm {

namespace {

enum class Phase { assembly, solve, step };

class ImplicitKernel final : public Kernel {
public:
    ImplicitKernel(const KernelConfig& cfg, Phase phase, std::string name) : phase_(phase), name_(std::move(name)) {
        case_ = cfg.choice("case");
        setup_.settings = cases().at(case_).what.settings;
        setup_.settings.integrator = Integrator::implicit;
        warm_steps_ = static_cast<long>(cfg.param("warm-steps"));
        multiple_ = cfg.param("dt-multiple");
        setup_.mesh = cfg.mesh.empty() ? box_spec_for(cfg.size) : cfg.mesh;
        setup_.ordering = cfg.access.name;
        setup_.particles = phase == Phase::assembly ? "sorted" : cfg.variant;
        setup_.sort_every = phase == Phase::step ? sort_every_of(cfg) : 0;
        setup_.sort_threshold = particle_orders().at(setup_.particles).what.sort_threshold;
        setup_.settings.per_element = static_cast<int>(cfg.param("ppe"));
        setup_.strategy = phase == Phase::assembly ? parse_strategy(cfg.variant)
                                                   : (cfg.threads > 1 ? Strategy::partition : Strategy::serial);
        setup_.threads = cfg.threads;
        setup_.seed = cfg.seed;
    }

    void setup(Arena& arena) override {
        {
            Setup probe = setup_;
            probe.settings.integrator = Integrator::explicit_step;
            const State p = build(probe);
            setup_.settings.dt = multiple_ * critical_step(p.grid, p.settings.material);
        }
        st_ = std::make_unique<State>(build(setup_, &arena));
        // The warm steps also count the iterations a step takes, which a step's work is declared
        // from (work() is asked before the timed steps): at least one is run for that.
        for (long k = 0; k < std::max(warm_steps_, 1L); ++k) advance(*st_, setup_);
        if (st_->implicit.failed_steps > 0)
            throw std::runtime_error(name_ + ": an untimed step failed: " + st_->implicit.failure);
        const double warm = static_cast<double>(st_->steps);
        warm_newton_ = static_cast<double>(st_->implicit.newton) / warm;
        warm_cg_ = static_cast<double>(st_->implicit.solver_iterations) / warm;
        if (particle_orders().at(setup_.particles).what.sorts) reorder(*st_, setup_, ReorderCause::start);
        reorderings_start_ = st_->order.count;
        touch_nodes(*st_, true);
        if (phase_ == Phase::step) equivalence_ = check_equivalence(setup_);
        if (phase_ != Phase::step) {
            // The first Newton system of the next step.
            implicit_project(*st_);
            implicit_assemble(*st_, true);
            implicit_residual(*st_);
            implicit_finish_tangent(*st_);
        }
        if (phase_ == Phase::solve) {
            place_system(arena);
            // A solve's iterations, the same in every repetition (the same system from δ = 0).
            last_iterations_ = jacobi_cg(cg_, st_->settings.implicit.cg_tol, st_->settings.implicit.cg_max, why_);
        }
        mass_ = mass_by_id(st_->particles);
        start_newton_ = st_->implicit.newton;
        start_cg_ = st_->implicit.solver_iterations;
        calls_ = 0;
    }

    void run(int calls) override {
        State& st = *st_;
        for (int c = 0; c < calls; ++c) {
            switch (phase_) {
                case Phase::assembly:
                    implicit_assemble(st, true);
                    break;
                case Phase::solve:
                    last_iterations_ = jacobi_cg(cg_, st.settings.implicit.cg_tol, st.settings.implicit.cg_max, why_);
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
        Verification v;
        if (calls_ == 0)
            failed = "no repetition ran";
        else
            switch (phase_) {
                case Phase::assembly:
                    what = "f_int and the tangent equal a serial assembly of the same particles (1e-12 of the largest)";
                    failed = against_serial();
                    break;
                case Phase::solve:
                    what = "the recursive residual CG stopped on within " +
                           format_number(st_->settings.implicit.cg_tol) +
                           ", ||r - K δ|| / ||r|| recomputed within it plus the rounding margin, δ equal to CHOLMOD's "
                           "solve (1e-8 of its largest)";
                    if (last_iterations_ < 0) {
                        failed = why_;
                        v.solver_failed = true;
                    } else {
                        std::copy(cg_.x, cg_.x + cg_.n, st_->system.delta.begin());
                        failed = against_cholmod();
                    }
                    break;
                case Phase::step:
                    what = "the first " + std::to_string(equivalence_steps) +
                           " steps equal natural order, serial, seeded (1e-10); every Newton converged; after " +
                           std::to_string(st_->steps) +
                           " steps: finite, inside the box, located, mass exact, Σ m_n = Σ m_p" +
                           reorderings_text(*st_, setup_, reorderings_start_);
                    if (st_->implicit.failed_steps > 0) {
                        failed = std::to_string(st_->implicit.failed_steps) +
                                 " step(s) failed, the last: " + st_->implicit.failure;
                        v.solver_failed = true;
                    }
                    if (failed.empty()) failed = equivalence_;
                    if (failed.empty()) failed = check_state(*st_, mass_);
                    break;
            }
        v.passed = failed.empty();
        v.detail = describe() + (failed.empty() ? what : "FAILED: " + failed);
        return v;
    }

    std::vector<Fact> facts() const override {
        const State& st = *st_;
        std::vector<Fact> f{{"particles", static_cast<double>(st.particles.size()), ""},
                            {"rows", static_cast<double>(st.system.rows()), "unknowns"},
                            {"nonzeros", static_cast<double>(st.system.val.size()), ""},
                            {"dt", st.dt, "s"}};
        if (phase_ == Phase::solve) {
            f.push_back({"cg-iterations", static_cast<double>(last_iterations_), "iterations"});
            // CHOLMOD's phases on the same system (verify's reference, in its own fill-reducing order).
            if (cholmod_.factorise > 0) {
                f.push_back({"cholmod-analyse-seconds", cholmod_.analyse, "s"});
                f.push_back({"cholmod-factor-seconds", cholmod_.factorise, "s"});
                f.push_back({"cholmod-solve-seconds", cholmod_.solve, "s"});
            }
        }
        if (phase_ == Phase::step) {
            const double steps = static_cast<double>(st.steps);
            f.push_back({"newton-per-step",
                         static_cast<double>(st.implicit.newton - start_newton_) /
                             std::max(1.0, static_cast<double>(calls_ * steps_per_call())),
                         "iterations"});
            f.push_back({"cg-per-newton",
                         static_cast<double>(st.implicit.solver_iterations - start_cg_) /
                             std::max<double>(1, static_cast<double>(st.implicit.newton - start_newton_)),
                         "iterations"});
            f.push_back({"simulated", st.time, "s"});
            if (particle_orders().at(setup_.particles).what.sorts)
                for (Fact& r : reordering_facts(st, setup_, reorderings_start_)) f.push_back(std::move(r));
            (void)steps;
        }
        if (phase_ == Phase::assembly && st.plan.strategy == Strategy::colour)
            f.push_back({"colours", static_cast<double>(st.plan.colours()), "barriers"});
        return f;
    }

    Work work() const override {
        const State& st = *st_;
        const double np = static_cast<double>(st.particles.size());
        const double nnz = static_cast<double>(st.system.val.size()), rows = static_cast<double>(st.system.rows());
        Work w;
        switch (phase_) {
            case Phase::assembly:
                w = assembly_work(np, nnz, rows);
                break;
            case Phase::solve:
                w = solve_work(static_cast<double>(std::max<long>(last_iterations_, 1)), nnz, rows);
                break;
            case Phase::step:
                // From the untimed steps' averages (the facts give the timed steps').
                w = step_work(steps_per_call(), np, warm_newton_, warm_cg_, nnz, rows);
                break;
        }
        w.hardware_bytes = w.stream_bytes;
        w.footprint_bytes = footprint(st) + static_cast<std::uint64_t>(12 * nnz + 8 * 16 * rows);
        return w;
    }

private:
    int steps_per_call() const { return steps_per_repetition(setup_.sort_every, 5); }
    std::string describe() const {
        return case_ + " on box grid " + setup_.mesh + " (" + std::to_string(st_->grid.elements()) + " tetrahedra, " +
               std::to_string(st_->particles.size()) + " particles, " + std::to_string(st_->system.rows()) +
               " rows, dt " + format_number(st_->dt) + " s = " + format_number(multiple_) +
               "x the explicit step, after " + std::to_string(warm_steps_) + " untimed steps), " + setup_.ordering +
               ", particles " + setup_.particles + ", " + strategy_name(st_->plan.strategy) + ": ";
    }

    // The solve's whole working set in the point's arena, so that --placement applies to it: the
    // matrix ("system-row-ptr", "system-col", "system-val") and the right-hand side and CG's six
    // vectors ("cg-b", "cg-x", ...), first touched by the threads of the CG's row loops (each its
    // static block of rows, and those rows' entries), copied from the system the step built.
    void place_system(Arena& arena) {
        const ActiveSystem& s = st_->system;
        const std::int64_t n = static_cast<std::int64_t>(s.rows());
        const std::size_t nnz = s.val.size();
        auto* rp = arena.allocate<std::uint32_t>("system-row-ptr", static_cast<std::size_t>(n) + 1);
        auto* col = arena.allocate<std::uint32_t>("system-col", nnz);
        auto* val = arena.allocate<double>("system-val", nnz);
        double* vec[7];
        const char* names[7] = {"cg-b", "cg-x", "cg-r", "cg-z", "cg-p", "cg-q", "cg-diag"};
        for (int k = 0; k < 7; ++k) vec[k] = arena.allocate<double>(names[k], static_cast<std::size_t>(n));
#pragma omp parallel
        {
            const Block b = my_block(n);
            for (std::int64_t i = b.lo; i < b.hi; ++i) {
                rp[i + 1] = s.row_ptr[static_cast<std::size_t>(i) + 1];
                for (std::uint32_t k = s.row_ptr[i]; k < s.row_ptr[i + 1]; ++k) col[k] = s.col[k], val[k] = s.val[k];
                vec[0][i] = s.r[static_cast<std::size_t>(i)];
                for (int v = 1; v < 7; ++v) vec[v][i] = 0;
            }
            if (b.lo == 0) rp[0] = 0;
        }
        cg_ = CgArrays{n, rp, col, val, vec[0], vec[1], vec[2], vec[3], vec[4], vec[5], vec[6]};
    }

    std::string against_serial() {
        State& st = *st_;
        const std::vector<double> f = st.system.fint, k = st.system.val;
        const ScatterPlan plan = st.plan;
        st.plan = plan_scatter(st.grid, Strategy::serial, 1);
        implicit_assemble(st, true);
        st.plan = plan;
        double fs = 0, ks = 0, fe = 0, ke = 0;
        for (std::size_t i = 0; i < f.size(); ++i)
            fs = std::max(fs, std::fabs(st.system.fint[i])), fe = std::max(fe, std::fabs(f[i] - st.system.fint[i]));
        for (std::size_t i = 0; i < k.size(); ++i)
            ks = std::max(ks, std::fabs(st.system.val[i])), ke = std::max(ke, std::fabs(k[i] - st.system.val[i]));
        if (!(fe <= 1e-12 * fs) || !(ke <= 1e-12 * ks))
            return "the strategy's force or tangent differs from the serial one by " + format_number(fe / fs) + ", " +
                   format_number(ke / ks) + " of the largest";
        return "";
    }

    std::string against_cholmod() {
        State& st = *st_;
        const ActiveSystem& s = st.system;
        // The true residual, || |K| |δ| || and the longest row for the rounding margin, and the recursive
        // residual CG stopped on (left in its r).
        double rr = 0, bb = 0, aa = 0, rec = 0;
        std::int64_t longest = 0;
        for (std::size_t i = 0; i < s.rows(); ++i) {
            double y = 0, abs_y = 0;
            for (std::uint32_t k = s.row_ptr[i]; k < s.row_ptr[i + 1]; ++k) {
                y += s.val[k] * s.delta[s.col[k]];
                abs_y += std::fabs(s.val[k] * s.delta[s.col[k]]);
            }
            longest = std::max<std::int64_t>(longest, s.row_ptr[i + 1] - s.row_ptr[i]);
            rr += (s.r[i] - y) * (s.r[i] - y);
            bb += s.r[i] * s.r[i];
            aa += abs_y * abs_y;
            rec += cg_.r[i] * cg_.r[i];
        }
        const double tol = st.settings.implicit.cg_tol,
                     margin = fem::cg_rounding_margin(last_iterations_, longest, std::sqrt(aa), std::sqrt(bb));
        if (bb > 0 && !(std::sqrt(rec) <= tol * std::sqrt(bb)))
            return "CG stopped at a recursive residual of " + format_number(std::sqrt(rec / bb)) +
                   ", above its tolerance " + format_number(tol);
        if (!(std::sqrt(rr) <= (tol + margin) * std::sqrt(bb)))
            return "the recomputed residual ||r - K δ|| / ||r|| is " + format_number(std::sqrt(rr / bb)) +
                   ", above the tolerance " + format_number(tol) + " + " + format_number(margin) + " (rounding)";
        if (!fem::sparse_libs_missing().empty()) return "";
        fem::Csr a;
        a.n = static_cast<std::int64_t>(s.rows());
        a.row_ptr = s.row_ptr;
        a.col = s.col;
        a.val = s.val;
        std::vector<double> ref;
        try {
            ref = fem::cholesky_solve(a, s.r, &cholmod_);
        } catch (const std::exception& e) {
            return std::string("CHOLMOD's reference solve failed: ") + e.what();
        }
        double scale = 0, err = 0;
        for (std::size_t i = 0; i < ref.size(); ++i)
            scale = std::max(scale, std::fabs(ref[i])), err = std::max(err, std::fabs(ref[i] - s.delta[i]));
        if (!(err <= 1e-8 * scale))
            return "CG's δ differs from CHOLMOD's by " + format_number(err / scale) + " of its largest";
        return "";
    }

    Phase phase_;
    std::string case_;
    long warm_steps_ = 5;
    double multiple_ = 10;
    Setup setup_;
    std::unique_ptr<State> st_;
    std::string equivalence_, why_;
    double mass_ = 0, warm_newton_ = 0, warm_cg_ = 0;
    fem::CholeskyTimes cholmod_;
    std::string name_;
    long calls_ = 0, last_iterations_ = 0;
    std::uint64_t reorderings_start_ = 0;  // the tracker's count where the timing starts
    std::uint64_t start_newton_ = 0, start_cg_ = 0;
    CgArrays cg_;  // the solve kernel's placed system
};

void add(const std::string& name, Phase phase, const std::string& formula, const std::string& notes) {
    KernelEntry e = mpm_entry(name, formula,
                              phase == Phase::step    ? "particle-step"
                              : phase == Phase::solve ? "cg-iteration"
                                                      : "particle",
                              phase == Phase::assembly, phase == Phase::step);
    e.info.params.push_back(
        {"dt-multiple", 10,
         "the implicit MPM step as a multiple of the explicit stable step, > 0 (mpm-implicit kernels)"});
    e.info.read_bytes_per_unit = phase == Phase::assembly ? assembly_particle_bytes
                                 : phase == Phase::step   ? step_particle_bytes
                                                          : 0;
    // Per particle (assembly); a solve's and a step's depend on the system and the iterations: 0 here, counted in each
    // record's work.
    e.info.flops_per_unit = phase == Phase::assembly ? assembly_flops : 0;
    e.info.notes = notes;
    e.default_meshes = {"box:16,16,16"};
    e.make = [phase, name](const KernelConfig& cfg) { return std::make_unique<ImplicitKernel>(cfg, phase, name); };
    e.validate = [name](const KernelConfig& cfg) {
        validate_mpm(cfg, name, cfg.mesh.empty() ? box_spec_for(cfg.size) : cfg.mesh);
        if (cases().at(cfg.choice("case")).what.fluid())
            throw UsageError(name + " --case=" + cfg.choice("case") +
                             ": the implicit integrator has the elastic material only; give --case=" + elastic_cases());
        const double m = cfg.param("dt-multiple");
        if (!(m > 0) || m > 1e4)
            throw UsageError("--dt-multiple=" + format_number(m) + " for " + name +
                             ": a number of explicit stable steps, > 0 and at most 10000");
    };
    register_kernel(std::move(e));
}

const bool registered = [] {
    add("mpm-implicit-assembly", Phase::assembly,
        "f_i += V_p P ∇N_i; K_ij += V_p (∇N_i·S∇N_j I + λ G_i⊗G_j + μ (∇N_i·∇N_j) F Fᵀ + μ G_j⊗G_i)",
        "implicit MPM: internal force and consistent tangent on the active grid; --strategy=" +
            join(strategies().names(), ",") + " (default all; serial on one thread)");
    add("mpm-implicit-solve", Phase::solve, "K δ = r by Jacobi-preconditioned CG, from δ = 0",
        "implicit MPM: one Newton system's linear solve; --particles=" + join(particle_orders().names(), ",") +
            " (dynamic renumbers the grid and the system)");
    add("mpm-implicit-step", Phase::step,
        "K whole implicit steps (projection, Newton: assembly and CG, update, locate), each with the reordering due",
        "implicit MPM (Newmark, Newton; --case: " + elastic_cases() +
            "), --dt-multiple, a repetition K = --sort-every steps (5 under auto, the default); --particles=" +
            join(particle_orders().names(), ",") + "");
    return true;
}();

}  // namespace

}  // namespace suite::mpm
