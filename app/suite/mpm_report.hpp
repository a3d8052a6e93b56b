#pragma once
// What `suite mpm` reports of a run (mpm_report.cpp): front.csv, the summary document mpm.json,
// and the summary printed at the end. They only render; mpm.cpp writes and prints them.
#include <string>

#include <nlohmann/json.hpp>

#include "kernels/mpm/mpm.hpp"
#include "kernels/mpm/simulation.hpp"

namespace suite::mpm_command {

// The run as mpm.cpp resolved it, beside the state and the outcome.
struct ReportInput {
    const mpm::State& st;  // after the run
    const mpm::Setup& setup;
    const mpm::SimulationSettings& run;
    const mpm::Outcome& outcome;
    nlohmann::json options;        // every option's value as used (the settings of mpm.json)
    double stable_dt = 0;          // the grid's and material's stable step (Courant number 1)
    std::string png;               // "" when front.png was drawn, else why not
    std::uint64_t warm_steps = 0;  // the rate after them is reported beside the whole run's
};

// step,time,front,kinetic_energy,dt,potential_energy,internal_energy,mean_curve_gap,same_element,
// top_settlement,stepping_seconds: one row a step from step 0, the numbers to 17 digits (the
// seconds to 9), top_settlement empty outside the column case.
std::string front_csv(const mpm::Outcome& r);
nlohmann::json summary_json(const ReportInput& in);
std::string summary_text(const ReportInput& in);

}  // namespace suite::mpm_command
