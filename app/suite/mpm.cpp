// `suite mpm`: kernels/mpm run as a simulation (--case: an elastic column's collapse or settlement,
// a water column's dam break). Every option is checked, and the state built (the library's own
// limits), before anything is written; then the steps and their checks (kernels/mpm/simulation),
// and into --out=DIR the snapshots (.vtu, .pvd), front.csv, mpm.json, front.png (mpm_report.cpp).
#include <omp.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <limits>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "app/suite/commands.hpp"
#include "app/suite/frame.hpp"
#include "app/suite/mpm_options.hpp"
#include "app/suite/mpm_report.hpp"
#include "app/suite/parse.hpp"
#include "app/suite/plotter.hpp"
#include "harness/common/output_file.hpp"
#include "harness/common/text.hpp"
#include "harness/common/units.hpp"
#include "harness/kernel/arena.hpp"
#include "kernels/mesh/mesh_spec.hpp"
#include "kernels/mpm/choices.hpp"
#include "kernels/mpm/mpm.hpp"
#include "kernels/mpm/simulation.hpp"
#include "kernels/mpm/vtk.hpp"

namespace suite {
namespace mpm_command {
namespace {

// --column=X,Y,Z: three finite numbers > 0.
void parse_column(const std::string& text, double* hi) {
    const std::vector<std::string> parts = split(text, ',');
    bool ok = parts.size() == 3;
    for (std::size_t a = 0; ok && a < 3; ++a) {
        try {
            hi[a] = parse_finite(parts[a], "--column");
            ok = hi[a] > 0;
        } catch (const UsageError&) {
            ok = false;
        }
    }
    if (!ok)
        throw UsageError("--column=" + text +
                         ": the material's region [0,X]x[0,Y]x[0,Z] is three finite numbers X,Y,Z > 0 in metres, e.g. "
                         "0.4,0.4,0.8 (the default)");
}

// A material constant that is a normal number > 0 (not 0, -0, a subnormal or an overflow): what
// the elastic step can divide by. The message echoes the value as typed.
double material_value(const std::string& text, const char* option, const char* what) {
    const double v = parse_finite(text, option);
    if (!(v >= std::numeric_limits<double>::min()) || v > 1e30)
        throw UsageError(std::string(option) + "=" + text + ": " + what + ", a number from 1e-300 to 1e30");
    return v;
}

// The setup the options ask for, every number checked; `given` tells which options were typed.
mpm::Setup setup_of(const Options& o, const CLI::App& given) {
    const mpm::Case& the_case = mpm::cases().at(o.case_name).what;
    mpm::grid_orderings().at(o.ordering);
    const mpm::ParticleOrder order = mpm::particle_orders().at(o.particles).what;
    const bool fluid = the_case.fluid();
    // An option of another case's material or region is refused, not ignored.
    const std::string takes = fluid ? " (a fluid: it takes --sound-speed, --viscosity and --density)"
                                    : " (an elastic solid: it takes --young, --poisson and --density)";
    for (const char* option : fluid ? std::vector<const char*>{"--young", "--poisson"}
                                    : std::vector<const char*>{"--sound-speed", "--viscosity"})
        if (given.count(option) > 0)
            throw UsageError(std::string(option) + " does not apply to --case=" + o.case_name + takes);
    if (the_case.column == mpm::ColumnOption::none && given.count("--column") > 0)
        throw UsageError("--column does not apply to --case=" + o.case_name +
                         (fluid ? takes : std::string(" (its region is the case's own)")));
    mpm::Setup s;
    s.settings = the_case.settings;
    s.mesh = o.mesh;
    s.ordering = o.ordering;
    s.particles = o.particles;
    s.sort_every = o.sort_every;
    s.sort_threshold = order.sort_threshold;
    s.threads = o.threads;
    s.seed = o.seed;
    s.force = o.force;
    s.strategy = o.strategy.empty() ? (o.threads == 1 ? mpm::Strategy::serial : mpm::Strategy::partition)
                                    : mpm::strategies().at(o.strategy).what;
    if (o.threads > omp_get_thread_limit())
        throw UsageError("--threads=" + std::to_string(o.threads) + ": OpenMP allows at most " +
                         std::to_string(omp_get_thread_limit()) + " (OMP_THREAD_LIMIT); ask for fewer or unset it");
    // An option the run would not use is refused rather than recorded as if it had been.
    if (given.count("--sort-every") > 0 && !order.sorts)
        throw UsageError(mpm::sort_every_text(o.sort_every) + ": --particles=" + o.particles +
                         " never reorders; give --particles=sorted or dynamic, "
                         "or leave --sort-every out");
    if (!o.sort_threshold.empty()) {
        if (!order.sorts || o.sort_every != mpm::sort_auto)
            throw UsageError("--sort-threshold=" + o.sort_threshold +
                             ": it applies to --sort-every=auto (the default) " +
                             "with --particles=sorted or dynamic, not " +
                             (order.sorts ? mpm::sort_every_text(o.sort_every) : "--particles=" + o.particles));
        s.sort_threshold = parse_finite(o.sort_threshold, "--sort-threshold");
        if (!(s.sort_threshold > 0) || s.sort_threshold > 1e9)
            throw UsageError("--sort-threshold=" + o.sort_threshold +
                             ": the decay a reordering costs, a number > 0 and at most 1e9 (default " +
                             format_number(order.sort_threshold) + " for --particles=" + o.particles + ")");
    }
    if (!o.renumber_share.empty()) {
        if (!order.renumbers || o.sort_every != mpm::sort_auto)
            throw UsageError("--renumber-share=" + o.renumber_share +
                             ": it applies to --sort-every=auto (the default) with --particles=dynamic, not " +
                             (order.renumbers ? mpm::sort_every_text(o.sort_every) : "--particles=" + o.particles));
        s.renumber_share = parse_finite(o.renumber_share, "--renumber-share");
        if (!(s.renumber_share >= 0 && s.renumber_share <= 1))
            throw UsageError("--renumber-share=" + o.renumber_share +
                             ": the share of the particles outside the last renumbering's elements, a number from 0 "
                             "to 1 (default " +
                             format_number(mpm::default_renumber_share) + ")");
    }
    if (o.warm_steps > 0 && o.warm_steps >= o.steps)
        throw UsageError("--warm-steps=" + std::to_string(o.warm_steps) +
                         ": the rate is measured over the steps after the warm ones, and --steps=" +
                         std::to_string(o.steps) + " leaves none; give fewer warm steps or more steps");
    if (given.count("--courant") > 0 && given.count("--dt") > 0 && parse_finite(o.dt, "--dt") != 0)
        throw UsageError("--courant=" + o.courant + " and --dt=" + o.dt +
                         ": the step is --dt's when it is given; give one of them");
    if (s.strategy == mpm::Strategy::partition && o.threads > 64)
        throw UsageError(
            "--threads=" + std::to_string(o.threads) + ": the partition strategy" +
            (o.strategy.empty() ? " (the default for more than one thread)" : "") +
            " takes at most 64 threads (one bit each per node); give --strategy=atomic or colour, or fewer threads");
    mpm::Settings& m = s.settings;
    m.per_element = o.ppe;
    if (fluid) {
        m.material.sound_speed =
            material_value(o.sound_speed, "--sound-speed", "the fluid's sound speed must be > 0 (m/s)");
        m.material.viscosity = parse_finite(o.viscosity, "--viscosity");
        if (!(m.material.viscosity >= 0) || m.material.viscosity > 1e30)
            throw UsageError("--viscosity=" + o.viscosity +
                             ": the fluid's dynamic viscosity is a number of Pa s from 0 to 1e30");
    } else {
        if (!o.young.empty())
            m.material.young = material_value(o.young, "--young", "Young's modulus E must be > 0 (Pa)");
        m.material.poisson = parse_finite(o.poisson, "--poisson");
        if (!(m.material.poisson > -1 && m.material.poisson < 0.5))
            throw UsageError("--poisson=" + o.poisson +
                             ": Poisson's ratio must lie in (-1, 0.5); 0.5 is incompressible, which an explicit "
                             "elastic step cannot take");
    }
    m.material.density = material_value(o.density, "--density", "the density must be > 0 (kg/m³)");
    if (!o.column.empty()) parse_column(o.column, m.region.hi);
    if (the_case.column == mpm::ColumnOption::full_width && (m.region.hi[0] != 1 || m.region.hi[1] != 1))
        throw UsageError("--column=" + o.column + " with --case=" + o.case_name +
                         ": the one-dimensional answer needs the layer to fill the box's width, --column=1,1,Z");
    m.courant = parse_finite(o.courant, "--courant");
    m.integration = mpm::integrations().at(o.integration).what;
    m.damping = parse_finite(o.damping, "--damping");
    if (m.damping < 0)
        throw UsageError("--damping=" + o.damping + ": the damping is a rate in 1/s, >= 0 (0, the default: none)");
    m.dt = parse_finite(o.dt, "--dt");
    if (m.dt < 0)
        throw UsageError("--dt=" + o.dt +
                         ": the time step is a number of seconds >= 0 (0, the default: from --courant)");
    m.integrator = mpm::parse_integrator(o.integrator);
    const bool implicit = m.integrator != mpm::Integrator::explicit_step;
    for (const char* option : {"--solver", "--newmark", "--strain", "--newton-max"})
        if (!implicit && given.count(option) > 0)
            throw UsageError(std::string(option) + " applies to --integrator=implicit or static, not explicit");
    if (implicit && given.count("--courant") > 0)
        throw UsageError(
            "--courant applies to --integrator=explicit; an implicit step is --dt (default 10 times the stable step)");
    m.implicit.solver = mpm::parse_linear_solver(o.solver);
    m.implicit.large_strain = mpm::strains().at(o.strain).what;
    m.implicit.newton_max = o.newton_max;
    const std::vector<std::string> nm = split(o.newmark, ',');
    if (nm.size() != 2)
        throw UsageError("--newmark=" + o.newmark +
                         ": Newmark's BETA,GAMMA, two numbers (default 0.25,0.5, average acceleration)");
    m.implicit.beta = parse_finite(nm[0], "--newmark");
    m.implicit.gamma = parse_finite(nm[1], "--newmark");
    if (m.integrator == mpm::Integrator::quasi_static && given.count("--newmark") > 0)
        throw UsageError("--newmark applies to --integrator=implicit (static has no inertia)");
    return s;
}

// A step the collapse can be resolved with: no longer than the time the column takes to fall its
// own height from rest under gravity. A material so soft or so dense that even its stable step
// is longer (--young=1e-3, --density=1e300) would fail at its first step, telling the user to
// shrink a --dt they never gave; it is refused here, with the numbers. (A --force'd step a few
// times the stable one stays allowed: that is how an unstable step is shown to be caught.)
void check_step_resolves_the_fall(const mpm::State& st, const Options& o, double stable) {
    const mpm::Settings& m = st.settings;
    const double g = std::sqrt(m.gravity[0] * m.gravity[0] + m.gravity[1] * m.gravity[1] + m.gravity[2] * m.gravity[2]);
    const double height = m.region.hi[2] - m.region.lo[2];
    const double fall = std::sqrt(2 * height / g);
    // The implicit tangent is M / (β dt²) + K, and M / (β dt²) outgrows K as (stable / dt)²: once
    // that passes 1 / ε the stiffness is lost in rounding and Newton meets NaN. Refused here.
    if (m.integrator == mpm::Integrator::implicit && m.dt > 0 &&
        st.dt < stable * std::sqrt(std::numeric_limits<double>::epsilon())) {
        char least[64];
        std::snprintf(least, sizeof least, "%.3g", stable * std::sqrt(std::numeric_limits<double>::epsilon()));
        throw UsageError("--dt=" + o.dt + ": so short that the implicit step's inertia term swamps the stiffness " +
                         "beyond what a double resolves; give at least " + least + " s");
    }
    if (st.dt <= fall) return;
    char numbers[256];
    std::snprintf(numbers, sizeof numbers,
                  "the step %.3g s is longer than the %.3g s the column takes to fall its %.3g m", st.dt, fall, height);
    if (m.dt > 0) throw UsageError("--dt=" + o.dt + ": " + numbers + "; give a smaller --dt");
    char wave[160];
    std::snprintf(wave, sizeof wave, " (the wave speed is %.3g m/s, so the stable step is %.3g s)",
                  m.material.wave_speed(), stable);
    if (m.material.model == mpm::Material::Model::fluid)
        throw UsageError("--sound-speed=" + o.sound_speed + " --viscosity=" + o.viscosity + ": " + numbers + wave +
                         ": no step could resolve the fall; give a larger --sound-speed");
    throw UsageError("--young=" + (o.young.empty() ? format_number(m.material.young) : o.young) +
                     " --density=" + o.density + ": " + numbers + wave +
                     ": no step could resolve the collapse; give a stiffer (larger --young) or lighter (smaller "
                     "--density) material");
}

// build(), with the region's messages named after the option that sets it.
mpm::State build_state(const mpm::Setup& s, const Options& o) {
    try {
        return mpm::build(s);
    } catch (const UsageError& e) {
        const std::string what = e.what();
        if (what.rfind("the material's region", 0) == 0 && !o.column.empty())
            throw UsageError("--column=" + o.column + ": " + what);
        throw;
    }
}

using Clock = std::chrono::steady_clock;

// The progress line: rewritten in place on a terminal (at most ten times a second), otherwise a
// line at every tenth of the run, so that a log shows progress without a line a step.
class Progress {
public:
    Progress(bool quiet, std::uint64_t steps, std::size_t particles)
        : on_(!quiet), tty_(isatty(STDERR_FILENO) != 0), steps_(steps), particles_(particles) {}

    void update(const mpm::State& st, double front, double stepping_s) {
        if (!on_) return;
        const std::uint64_t k = st.steps;
        const auto now = Clock::now();
        if (tty_) {
            if (k != steps_ && std::chrono::duration<double>(now - last_).count() < 0.1) return;
        } else {
            // The first step at or past the next tenth of the run.
            if (k * 10 < next_tenth_ * steps_) return;
            while (next_tenth_ <= 10 && k * 10 >= next_tenth_ * steps_) ++next_tenth_;
        }
        last_ = now;
        const double rate = stepping_s > 0 ? static_cast<double>(particles_) * static_cast<double>(k) / stepping_s : 0;
        std::fprintf(stderr, "%sstep %llu/%llu  t = %.4g s  front %.4f m  %.3g particle-steps/s%s",
                     tty_ ? "\r\033[K" : "", static_cast<unsigned long long>(k),
                     static_cast<unsigned long long>(steps_), st.time, front, rate, tty_ ? "" : "\n");
        std::fflush(stderr);
        shown_ = true;
    }
    // Clears the line on a terminal, so that what follows starts on a clean one.
    void finish() {
        if (on_ && tty_ && shown_) std::fprintf(stderr, "\r\033[K");
        std::fflush(stderr);
    }

private:
    bool on_, tty_, shown_ = false;
    std::uint64_t steps_;
    std::size_t particles_;
    std::uint64_t next_tenth_ = 1;
    Clock::time_point last_{};
};

}  // namespace
}  // namespace mpm_command

int cmd_mpm(const std::vector<std::string>& args) {
    using namespace mpm_command;
    CLI::App app{
        "suite mpm: the Material Point Method's dam collapse, dam break or settling column, with particle snapshots "
        "for ParaView, the front and the particles' order against time"};
    Options o;
    add_mpm_options(app, o);
    if (!parse_command_line(app, "suite mpm", args)) return 0;

    // Everything is checked, and the state built, before any file or directory is made.
    const mpm::Setup setup = setup_of(o, app);
    if (!o.no_png) require_plotter("mpm_front.py", "--no-png");
    if (o.out.empty() && !o.dry_run)
        throw UsageError(
            "suite mpm needs --out=DIR, the directory for its snapshots, front.csv, mpm.json and front.png (or "
            "--dry-run)");
    const mesh::MeshSpec spec = mesh::parse_mesh_spec(o.mesh);
    const std::vector<FileIdentity> inputs =
        identify_inputs({spec.kind == mesh::MeshSpec::Kind::file ? spec.path : ""});
    const DirPolicy policy{.option = "--out", .command = "suite mpm", .inputs = inputs, .replace_earlier = o.replace};
    if (!o.out.empty()) OutputDir::check(o.out, policy);
    omp_set_num_threads(o.threads);
    mpm::State st = build_state(setup, o);
    const double stable = mpm::critical_step(st.grid, st.settings.material);
    check_step_resolves_the_fall(st, o, stable);
    const std::uint64_t snapshots = mpm::snapshot_count(o.steps, o.vtk_every);
    if (o.dry_run) {
        const std::uint64_t memory = mpm::state_bytes(mesh::mesh_counts(spec), st.particles.size(), 1,
                                                      setup.settings.integrator != mpm::Integrator::explicit_step);
        std::printf(
            "%s on %s: %zu particles, %zu elements, %zu nodes; dt %.4g s (%.3g of the stable %.4g s); %llu steps to t "
            "= %.4g s; "
            "%s integrator, %s grid, %s particles, %s scatter, %d thread(s); about %s of memory (%s available)\n",
            o.case_name.c_str(), o.mesh.c_str(), st.particles.size(), st.grid.elements(), st.grid.nodes(), st.dt,
            st.dt / stable, stable, static_cast<unsigned long long>(o.steps), st.dt * static_cast<double>(o.steps),
            mpm::integrator_name(setup.settings.integrator), setup.ordering.c_str(), setup.particles.c_str(),
            mpm::strategy_name(setup.strategy), setup.threads, format_bytes(memory).c_str(),
            format_bytes(available_memory_bytes(MemoryPolicy{})).c_str());
        if (o.out.empty())
            std::printf("no --out: nothing would be written\n");
        else
            std::printf("into %s: %llu snapshot(s) particles_SSSSSS.vtu%s, front.csv, mpm.json%s\n", o.out.c_str(),
                        static_cast<unsigned long long>(snapshots), snapshots ? " and particles.pvd" : "",
                        o.no_png ? "" : ", front.png");
        return 0;
    }
    CommandFrame frame("suite");
    OutputDir& out = frame.claim_dir(o.out, policy);

    mpm::SimulationSettings run;
    run.steps = o.steps;
    run.column = mpm::cases().at(o.case_name).what.reference == mpm::Reference::settlement;
    run.free_fall = mpm::cases().at(o.case_name).what.reference == mpm::Reference::free_fall;
    run.vtk_every = o.vtk_every;
    run.stop = frame.stop_flag();
    Progress progress(o.quiet, o.steps, st.particles.size());
    mpm::SimulationHooks hooks;
    hooks.snapshot = [&out](const std::string& name, const std::string& vtu) { out.write(name, vtu); };
    hooks.progress = [&progress](const mpm::State& now, double front, double stepping_s) {
        progress.update(now, front, stepping_s);
    };
    const mpm::Outcome r = mpm::simulate(st, setup, run, hooks);
    progress.finish();
    out.write("front.csv", front_csv(r));
    if (!r.snapshots.empty()) out.write("particles.pvd", mpm::collection_pvd(r.snapshots));
    ReportInput report{st, setup, run, r, options_json(o, setup), stable, "--no-png", o.warm_steps};
    out.write("mpm.json", summary_json(report).dump(1) + "\n");
    if (!o.no_png) {
        const Plotter p = find_plotter("mpm_front.py");
        report.png =
            p.reason.empty() ? out.with_writer([&p](const std::string& dir) { return draw(p, dir); }) : p.reason;
        if (!report.png.empty()) std::cerr << "suite: note: no front.png: " << report.png << "\n";
        out.write("mpm.json", summary_json(report).dump(1) + "\n");
    }
    if (!o.quiet) {
        std::printf("%s", summary_text(report).c_str());
        std::printf("wrote %s (%zu snapshot(s)%s, front.csv, mpm.json%s)\n", o.out.c_str(), r.snapshots.size(),
                    r.snapshots.empty() ? "" : " and particles.pvd", report.png.empty() ? ", front.png" : "");
    }
    std::fflush(stdout);
    if (!r.passed()) {
        std::cerr << "suite: error: mpm check failed: " << r.failure << "\n";
        // The solver's own status, as suite fem's: Newton or a linear solve failed, not the physics.
        return frame.finish(r.solver_failed ? 3 : 1,
                            std::to_string(r.steps_done) + " of " + std::to_string(o.steps) + " step(s)", false);
    }
    return frame.finish(0, std::to_string(r.steps_done) + " of " + std::to_string(o.steps) + " step(s)",
                        r.steps_done == o.steps);
}

}  // namespace suite
