#pragma once
// `suite mpm`'s options as given (mpm.cpp parses them; mpm_report.cpp records them in mpm.json).
#include <cstdint>
#include <string>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "kernels/mpm/mpm.hpp"

namespace suite::mpm_command {

struct Options {
    std::string case_name = "dam-collapse";
    std::string mesh = "box:16,16,16";
    std::string ordering = sfc::as_given_name();
    std::string particles = "seeded";
    int sort_every = mpm::sort_auto;  // --sort-every: auto or K
    std::string sort_threshold;       // "": mpm::default_sort_threshold
    std::string renumber_share;       // "": mpm::default_renumber_share
    std::string strategy;             // "": serial for 1 thread, partition for more
    int threads = 1;
    int ppe = 4;
    std::string young, poisson = "0.3", density = "1000";  // young "": the case's (mpm::cases())
    std::string sound_speed = "35", viscosity = "1e-3";
    std::string column;  // "": the case's
    std::string courant = "0.8", dt = "0", damping = "0";
    std::string integration = "mixed";
    std::string integrator = "explicit", solver = "cg", newmark = "0.25,0.5", strain = "large";
    int newton_max = 25;
    bool force = false;
    std::uint64_t seed = 1;
    std::uint64_t steps = 1000, vtk_every = 50, warm_steps = 0;
    std::string out;
    bool no_png = false, dry_run = false, quiet = false, replace = false;
};

// Declares every option of `suite mpm` on `app`, its help and the help's footer (mpm_cli.cpp).
void add_mpm_options(CLI::App& app, Options& o);

// Every option's value as used: the "settings" of mpm.json.
nlohmann::json options_json(const Options& o, const mpm::Setup& s);

}  // namespace suite::mpm_command
