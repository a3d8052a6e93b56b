#include "app/suite/mpm_report.hpp"

#include <cmath>
#include <cstdio>

#include "app/suite/mpm_options.hpp"
#include "harness/common/units.hpp"
#include "kernels/mpm/choices.hpp"

namespace suite::mpm_command {

namespace {

std::string fmt(const char* f, double v) {
    char b[64];
    std::snprintf(b, sizeof b, f, v);
    return b;
}

// NaN when no step was timed (--steps=0, or stopped before the first): not measured, never 0.
double particle_rate(const ReportInput& in) {
    const mpm::Outcome& r = in.outcome;
    return r.stepping_s > 0 && r.steps_done > 0
               ? static_cast<double>(in.st.particles.size()) * static_cast<double>(r.steps_done) / r.stepping_s
               : NAN;
}

nlohmann::json or_null(double v) { return std::isnan(v) ? nlohmann::json(nullptr) : nlohmann::json(v); }

bool particle_sorts(const mpm::Setup& s) { return mpm::particle_orders().at(s.particles).what.sorts; }
bool particle_renumbers(const mpm::Setup& s) { return mpm::particle_orders().at(s.particles).what.renumbers; }

// When the particles were reordered and why (front.csv's column `reordered` marks the same steps).
nlohmann::json reorderings_json(const ReportInput& in) {
    const mpm::OrderTracker& t = in.st.order;
    if (!particle_sorts(in.setup)) return nullptr;
    nlohmann::json list = nlohmann::json::array();
    std::uint64_t decayed = 0, every = 0;
    const bool automatic = in.setup.sort_every == mpm::sort_auto;
    const bool renumbers = particle_renumbers(in.setup);
    for (const mpm::Reordering& r : t.log) {
        decayed += r.cause == mpm::ReorderCause::decayed ? 1 : 0;
        every += r.cause == mpm::ReorderCause::every ? 1 : 0;
        list.push_back({{"step", r.step},
                        {"cause", mpm::reorder_cause_name(r.cause)},
                        {"decay", r.decay},
                        {"same_element_before", r.same_before},
                        {"same_element_after", r.same_after},
                        {"outside", renumbers ? nlohmann::json(r.outside) : nlohmann::json(nullptr)},
                        {"renumbered", r.renumbered}});
    }
    return {
        {"schedule", automatic ? "auto" : "every " + std::to_string(in.setup.sort_every) + " steps"},
        {"threshold", automatic ? nlohmann::json(in.setup.sort_threshold) : nlohmann::json(nullptr)},
        {"renumber_share", automatic && renumbers ? nlohmann::json(in.setup.renumber_share) : nlohmann::json(nullptr)},
        {"count", t.count},
        {"renumbered", renumbers ? nlohmann::json(t.renumberings) : nlohmann::json(nullptr)},
        {"decayed", decayed},
        {"every", every},
        {"listed", t.log.size()},
        {"list", list},
        {"detail",
         "after step `step`: start (the first), every (K steps since the last), decayed (auto: `decay`, the sum "
         "over the steps since the last of how far same_element fell below its value after that one, reached "
         "the threshold); same_element before and after the reordering; dynamic: outside (the share of the "
         "particles in elements that held none at the last renumbering, before this one) and whether the grid was "
         "renumbered "
         "(always at start and every; under auto where outside reached renumber_share)"}};
}

const char* const no_step = "no step was taken (--steps=0, or the run stopped before its first step)";

// Over the steps after --warm-steps (rows[k] is after k steps); NaN when none ran after them.
double rate_after_warm(const ReportInput& in) {
    const mpm::Outcome& r = in.outcome;
    if (in.warm_steps == 0 || r.steps_done <= in.warm_steps || r.rows.size() <= r.steps_done) return NAN;
    const double s = r.rows[r.steps_done].stepping_s - r.rows[in.warm_steps].stepping_s;
    return s > 0 ? static_cast<double>(in.st.particles.size()) * static_cast<double>(r.steps_done - in.warm_steps) / s
                 : NAN;
}

}  // namespace

std::string front_csv(const mpm::Outcome& r) {
    std::string out =
        "step,time,front,kinetic_energy,dt,potential_energy,internal_energy,mean_curve_gap,same_element,top_settlement,"
        "reordered,stepping_seconds\n";
    char line[400], settled[32];
    for (const auto& row : r.rows) {
        // The column's settlement; empty in the other cases (not measured, not 0).
        if (std::isnan(row.settlement))
            settled[0] = 0;
        else
            std::snprintf(settled, sizeof settled, "%.17g", row.settlement);
        std::snprintf(line, sizeof line, "%llu,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%s,%s,%.9g\n",
                      static_cast<unsigned long long>(row.step), row.time, row.front, row.kinetic, row.dt,
                      row.potential, row.internal, row.order.mean_gap, row.order.same_element, settled,
                      mpm::reorder_cause_name(row.reordered), row.stepping_s);
        out += line;
    }
    return out;
}

nlohmann::json summary_json(const ReportInput& in) {
    const mpm::Outcome& r = in.outcome;
    const mpm::State& st = in.st;
    const double rate = particle_rate(in);
    nlohmann::json checks = nlohmann::json::array();
    for (const auto& c : r.checks) checks.push_back({{"check", c.name}, {"passed", c.passed}, {"detail", c.detail}});
    nlohmann::json snapshots = nlohmann::json::array();
    for (std::size_t i = 0; i < r.snapshots.size(); ++i)
        snapshots.push_back(
            {{"file", r.snapshots[i].file}, {"step", r.snapshot_steps[i]}, {"time", r.snapshots[i].time}});
    nlohmann::json doc = {
        {"command", "suite mpm"},
        {"settings", in.options},
        {"complete", r.signal == 0 && r.passed() && r.steps_done == in.run.steps},
        {"counts", {{"particles", st.particles.size()}, {"elements", st.grid.elements()}, {"nodes", st.grid.nodes()}}},
        {"dt", st.dt},
        {"stable_dt", in.stable_dt},
        {"wave_speed", st.settings.material.wave_speed()},
        {"steps", r.steps_done},
        {"steps_asked", in.run.steps},
        {"simulated_time", st.time},
        {"timing",
         {{"wall_seconds", r.wall_s},
          {"stepping_seconds", r.stepping_s},
          {"particle_steps_per_second", or_null(rate)},
          {"particle_steps_per_second_per_thread", or_null(rate / in.setup.threads)},
          {"particle_steps_per_second_after_warm",
           std::isnan(rate_after_warm(in)) ? nlohmann::json(nullptr) : nlohmann::json(rate_after_warm(in))},
          {"warm_steps", in.warm_steps},
          {"threads", in.setup.threads},
          {"detail",
           "stepping: mpm::advance alone (the steps and the reorderings due); wall: the loop with the checks, "
           "snapshots and progress"}}},
        {"front",
         {{"initial", r.rows.empty() ? nlohmann::json(nullptr) : nlohmann::json(r.rows.front().front)},
          {"final", r.rows.empty() ? nlohmann::json(nullptr) : nlohmann::json(r.rows.back().front)},
          {"column_width", in.setup.settings.region.hi[0]}}},
        {"mass",
         {{"initial", r.mass_initial},
          {"final", r.mass_final},
          {"drift_relative", (r.mass_final - r.mass_initial) / r.mass_initial},
          {"nodal", r.nodal_mass},
          {"nodal_error_relative", r.nodal_error}}},
        {"dt_range",
         r.steps_done == 0 ? nlohmann::json(nullptr) : nlohmann::json{{"min", st.dt_min}, {"max", st.dt_max}}},
        {"energy",
         r.rows.empty()
             ? nlohmann::json(nullptr)
             : nlohmann::json{{"initial", r.rows.front().kinetic + r.rows.front().potential + r.rows.front().internal},
                              {"final", r.rows.back().kinetic + r.rows.back().potential + r.rows.back().internal},
                              {"detail", "kinetic + potential (above z = 0) + internal (mpm::energy), J"}}},
        {"locality", r.rows.empty() ? nlohmann::json(nullptr)
                                    : nlohmann::json{{"initial",
                                                      {{"mean_curve_gap", r.rows.front().order.mean_gap},
                                                       {"same_element", r.rows.front().order.same_element}}},
                                                     {"final",
                                                      {{"mean_curve_gap", r.rows.back().order.mean_gap},
                                                       {"same_element", r.rows.back().order.same_element}}},
                                                     {"detail",
                                                      "mean_curve_gap: the mean distance along the element curve "
                                                      "between consecutive particles' elements "
                                                      "(elements); same_element: the share of consecutive particles in "
                                                      "one element; each step in front.csv"}}},
        {"reorderings", reorderings_json(in)},
        {"column",
         std::isnan(r.settlement_exact)
             ? nlohmann::json(nullptr)
             : nlohmann::json{{"settlement_exact", r.settlement_exact},
                              {"settlement_measured", r.settlement_measured},
                              {"error_relative", r.settlement_error},
                              {"stress_rms_relative",
                               std::isnan(r.stress_rms) ? nlohmann::json(nullptr) : nlohmann::json(r.stress_rms)},
                              {"stress_profile_rms_relative", std::isnan(r.stress_profile)
                                                                  ? nlohmann::json(nullptr)
                                                                  : nlohmann::json(r.stress_profile)},
                              {"detail",
                               "the top particle layer's mean settlement against rho g (H z0 - z0^2/2) / M; damped: "
                               "the mean of the last tenth "
                               "of the steps and the RMS of szz + rho g (H - z0) over all particles relative to rho g "
                               "H; undamped: the mean "
                               "over the run, stress not compared"}}},
        {"free_fall", r.fall_steps == 0
                          ? nlohmann::json(nullptr)
                          : nlohmann::json{{"steps_in_flight", r.fall_steps},
                                           {"worst_from_exact", r.fall_worst},
                                           {"mean_from_analytic", r.fall_analytic},
                                           {"step_bound", r.fall_bound},
                                           {"detail",
                                            "before a wall acted: the largest distance of a particle from "
                                            "the explicit step's exact fall, and the mean fall's distance "
                                            "from g t^2 / 2 against g t dt / 2, m"}}},
        {"clamped", st.clamped},
        {"implicit",
         st.settings.integrator == mpm::Integrator::explicit_step
             ? nlohmann::json(nullptr)
             : nlohmann::json{{"newton_iterations",
                               r.steps_done == 0 ? nlohmann::json(nullptr) : nlohmann::json(st.implicit.newton)},
                              {"newton_max_per_step", st.implicit.max_newton},
                              {"cg_iterations", st.implicit.solver_iterations},
                              {"backtracks", st.implicit.backtracks},
                              {"cholmod_fallbacks", st.implicit.fallbacks},
                              {"worst_final_residual", r.steps_done == 0 ? nlohmann::json(nullptr)
                                                                         : nlohmann::json(st.implicit.worst_residual)},
                              {"last_residuals", st.implicit.last_residuals},
                              {"active_rows", st.implicit.active_rows},
                              {"nonzeros", st.implicit.nonzeros},
                              {"patterns_built", st.system.patterns},
                              {"detail",
                               "Newton iterations and CG iterations over all steps; residuals ||r_k|| / "
                               "max(||r_0||, ||m g||) of the last step"}}},
        {"verification", {{"passed", r.passed()}, {"checks", checks}}},
        {"snapshots", snapshots},
        {"files",
         {{"front_csv", "front.csv"},
          {"collection", r.snapshots.empty() ? nlohmann::json(nullptr) : nlohmann::json("particles.pvd")}}},
    };
    if (r.steps_done == 0) {
        // What stands for nothing is null above; this says why, once.
        doc["not_measured"] = no_step;
        doc["timing"]["rate_reason"] = no_step;
    }
    if (!r.passed()) doc["verification"]["failure"] = r.failure;
    if (r.signal) doc["interrupted_by_signal"] = r.signal;
    if (in.png.empty())
        doc["files"]["png"] = "front.png";
    else
        doc["files"]["png"] = {{"available", false}, {"reason", in.png}};
    return doc;
}

std::string summary_text(const ReportInput& in) {
    const mpm::Outcome& r = in.outcome;
    const mpm::State& st = in.st;
    const mpm::Setup& s = in.setup;
    const double rate = particle_rate(in);
    const double front0 = r.rows.empty() ? 0 : r.rows.front().front, front1 = r.rows.empty() ? 0 : r.rows.back().front;
    std::string t;
    const auto line = [&t](const std::string& label, const std::string& text) {
        char b[32];
        std::snprintf(b, sizeof b, "  %-14s ", label.c_str());
        t += b + text + "\n";
    };
    t += "suite mpm: " + in.options.value("case", std::string("dam-collapse")) + " on " + s.mesh + " (" + s.ordering +
         " grid, " + s.particles + " particles, " + mpm::strategy_name(s.strategy) + " scatter, " +
         std::to_string(s.threads) + " thread" + (s.threads == 1 ? "" : "s") + ")\n";
    line("particles", std::to_string(st.particles.size()) + " (" + std::to_string(s.settings.per_element) +
                          " per element of the column)");
    line("grid", std::to_string(st.grid.elements()) + " elements, " + std::to_string(st.grid.nodes()) + " nodes");
    if (s.settings.integrator != mpm::Integrator::explicit_step)
        line("integrator", std::string(mpm::integrator_name(s.settings.integrator)) + ", " +
                               (s.settings.implicit.large_strain ? "large" : "small") + " strain, " +
                               mpm::linear_solver_name(s.settings.implicit.solver) + "; the last system " +
                               std::to_string(st.implicit.active_rows) + " rows, " +
                               std::to_string(st.implicit.nonzeros) + " nonzeros");
    if (st.dt_max > st.dt_min)
        line("dt", fmt("%.4g", st.dt_min) + fmt(" to %.4g s", st.dt_max) +
                       " (following the fastest particle; at rest " + fmt("%.4g s", in.stable_dt) + " is stable)");
    else
        line("dt", fmt("%.4g s", st.dt) + " (" + fmt("%.3g", st.dt / in.stable_dt) + " of the stable " +
                       fmt("%.4g s", in.stable_dt) + ")");
    line("steps", std::to_string(r.steps_done) +
                      (r.steps_done == in.run.steps ? "" : " of " + std::to_string(in.run.steps)) + ", simulated " +
                      fmt("%.4g s", st.time));
    line("wall", fmt("%.3f s", r.wall_s) + " (stepping " + fmt("%.3f s", r.stepping_s) + ")");
    if (std::isnan(rate))
        line("rate", std::string("not measured: ") + no_step);
    else
        line("rate", fmt("%.4g particle-steps/s", rate) + fmt(" (%.4g per thread)", rate / s.threads));
    if (!std::isnan(rate_after_warm(in)))
        line("after warm-up", fmt("%.4g particle-steps/s", rate_after_warm(in)) + " over steps " +
                                  std::to_string(in.warm_steps + 1) + " to " + std::to_string(r.steps_done));
    line("front",
         fmt("%.6g m", front0) + " -> " + fmt("%.6g m", front1) + fmt(" (column width %g m)", s.settings.region.hi[0]));
    if (std::isnan(r.mass_final))
        line("mass drift", "not checked (the run stopped at a failed check)");
    else
        line("mass drift", fmt("%.3g", (r.mass_final - r.mass_initial) / r.mass_initial) + " relative" +
                               fmt("; nodal mass of a final P2G within %.3g", r.nodal_error));
    if (!r.rows.empty())
        line("order", fmt("%.3g", r.rows.front().order.mean_gap) +
                          fmt(" -> %.3g elements along the curve between neighbours", r.rows.back().order.mean_gap) +
                          fmt(", %.0f", 100 * r.rows.front().order.same_element) +
                          fmt(" -> %.0f %% in one element", 100 * r.rows.back().order.same_element));
    if (particle_sorts(in.setup))
        line("reorderings",
             std::to_string(st.order.count) + " (the start's included), " +
                 (in.setup.sort_every == mpm::sort_auto
                      ? "when the order had decayed past " + format_number(in.setup.sort_threshold) + " (auto)"
                      : mpm::sort_every_text(in.setup.sort_every)) +
                 (particle_renumbers(in.setup)
                      ? "; the grid renumbered at " + std::to_string(st.order.renumberings) + " of them"
                      : std::string()));
    line("clamped", std::to_string(st.clamped) + " particle position(s) pulled back onto a wall, in all");
    for (const auto& c : r.checks)
        line(c.name == "finite and inside the box" ? "NaN check" : c.name,
             (c.passed ? "passed: " : "FAILED: ") + c.detail);
    return t;
}

nlohmann::json options_json(const Options& o, const mpm::Setup& s) {
    const mpm::Settings& m = s.settings;
    return {
        {"case", o.case_name},
        {"mesh", s.mesh},
        {"ordering", s.ordering},
        {"particles", s.particles},
        {"sort_every", s.sort_every == mpm::sort_auto ? nlohmann::json("auto") : nlohmann::json(s.sort_every)},
        {"sort_threshold", s.sort_every == mpm::sort_auto && particle_sorts(s) ? nlohmann::json(s.sort_threshold)
                                                                               : nlohmann::json(nullptr)},
        {"renumber_share", s.sort_every == mpm::sort_auto && particle_renumbers(s) ? nlohmann::json(s.renumber_share)
                                                                                   : nlohmann::json(nullptr)},
        {"strategy", mpm::strategy_name(s.strategy)},
        {"threads", s.threads},
        {"ppe", m.per_element},
        {"material", m.material.model == mpm::Material::Model::fluid ? "fluid" : "elastic"},
        {"young",
         m.material.model == mpm::Material::Model::fluid ? nlohmann::json(nullptr) : nlohmann::json(m.material.young)},
        {"poisson", m.material.model == mpm::Material::Model::fluid ? nlohmann::json(nullptr)
                                                                    : nlohmann::json(m.material.poisson)},
        {"sound_speed", m.material.model == mpm::Material::Model::fluid ? nlohmann::json(m.material.sound_speed)
                                                                        : nlohmann::json(nullptr)},
        {"viscosity", m.material.model == mpm::Material::Model::fluid ? nlohmann::json(m.material.viscosity)
                                                                      : nlohmann::json(nullptr)},
        {"density", m.material.density},
        {"column", {m.region.hi[0], m.region.hi[1], m.region.hi[2]}},
        {"gravity", {m.gravity[0], m.gravity[1], m.gravity[2]}},
        {"courant", m.courant},
        {"damping", m.damping},
        {"integration", m.integration == mpm::Integration::mixed ? "mixed" : "particle"},
        {"integrator", mpm::integrator_name(m.integrator)},
        {"solver", m.integrator == mpm::Integrator::explicit_step
                       ? nlohmann::json(nullptr)
                       : nlohmann::json(mpm::linear_solver_name(m.implicit.solver))},
        {"newmark", m.integrator == mpm::Integrator::implicit ? nlohmann::json{m.implicit.beta, m.implicit.gamma}
                                                              : nlohmann::json(nullptr)},
        {"strain", m.integrator == mpm::Integrator::explicit_step
                       ? nlohmann::json(nullptr)
                       : nlohmann::json(m.implicit.large_strain ? "large" : "small")},
        {"newton_max", m.integrator == mpm::Integrator::explicit_step ? nlohmann::json(nullptr)
                                                                      : nlohmann::json(m.implicit.newton_max)},
        {"dt_given", m.dt},
        {"force", s.force},
        {"seed", s.seed},
        {"steps", o.steps},
        {"warm_steps", o.warm_steps},
        {"vtk_every", o.vtk_every}};
}

}  // namespace suite::mpm_command
