// `suite mpm`'s options, their help and the help's footer: what a user reads with --help.
#include <string>

#include <CLI/CLI.hpp>

#include "app/suite/mpm_options.hpp"
#include "app/suite/parse.hpp"
#include "harness/common/units.hpp"
#include "kernels/mpm/choices.hpp"

namespace suite::mpm_command {
namespace {

const char* const footer =
    R"(Explicit MPM, update stress last, linear tetrahedra (kernels/mpm/mpm.hpp). dt is --courant times
the stable step (the smallest element altitude over the wave speed; for the fluid over the sound
speed plus the fastest particle's speed, again before every step) unless --dt gives one; a dt
above the stable step is refused without --force. The front is the largest x of any particle.
--integrator=implicit: Newmark (--newmark) on the active nodes' displacement increment, Newton's
method with the consistent tangent (--strain), each linear solve by --solver, any --dt (default
10 times the stable step); static: no inertia, each step an equilibrium under gravity. Elastic
cases only; docs/mpm.md, "Implicit MPM". Their runs check the total energy too.

After every step each particle's position and velocity must be finite and inside the box, and
the kinetic energy at most 1.5 times what gravity can release from the start (more was made by
an unstable step, which the walls can keep finite); at the end each particle's mass must be its
initial one exactly, and a P2G of the final particles must put their total mass on the nodes to
1e-12. The first check that fails stops the run.

Examples:
  ./suite mpm --case=dam-collapse --steps=1000 --vtk-every=50 --out=dam
  ./suite mpm --case=dam-break --mesh=box:24,24,24 --steps=3000 --vtk-every=100 --out=water
  ./suite mpm --case=column --damping=10 --steps=1600 --vtk-every=0 --out=column     # the analytical check
  ./suite mpm --case=column --integrator=static --strain=small --steps=2 --vtk-every=0 --out=col   # the same, static
  ./suite mpm --integrator=implicit --dt=0.05 --steps=40 --out=dam-implicit           # 20x the stable step
  ./suite mpm --mesh=box:8,8,8 --steps=200 --vtk-every=20 --out=small        # a quick look
  ./suite mpm --mesh=box:24,24,24 --ordering=hilbert --particles=dynamic --threads=2 --out=dam24
  ./suite mpm --young=2e5 --poisson=0.25 --column=0.3,1,0.6 --steps=2000 --vtk-every=100 --out=wall
  ./suite mpm --mesh=box:16,16,16 --steps=500 --dry-run                       # the counts and dt, nothing written

In DIR: particles_SSSSSS.vtu (the particles after SSSSSS steps: at 0, every --vtk-every steps
and after the last; point data id, velocity, stress xx yy zz xy yz zx, volume, mass; base64
binary) and particles.pvd (them with their times, for ParaView), front.csv (step, time, front,
kinetic energy), mpm.json (settings, counts, checks, timing), front.png (front against time).
A progress line goes to stderr (rewritten in place on a terminal, else a line every 10 %).

Exit status: 0 ok; 1 a check failed (a NaN or infinite position or velocity, a particle outside
the box, kinetic energy beyond the bound, mass not conserved) or a file could not be written; 2 bad usage (one line on stderr,
nothing written); 3 an implicit step failed (Newton did not converge in its limit, a linear solve
did not, a singular system: mpm.json's Newton check says which); 130/143 interrupted (the files of the steps done are written, mpm.json says
"complete": false).
)";

}  // namespace

void add_mpm_options(CLI::App& app, Options& o) {
    app.footer(
        "\nThe cases (--case), each in the grid's box (box:NX,NY,NZ is the unit cube), at rest and\n"
        "unstressed at the start, under gravity (9.81 m/s² down z), the box's faces slip walls; the\n"
        "elastic ones take --young, --poisson, --density, the fluid --sound-speed, --viscosity, --density:\n" +
        mpm::cases().listed() + footer);
    app.get_formatter()->column_width(30);
    app.add_option(
        "--case", o.case_name,
        "the simulation: " + mpm::cases().accepted() + " (default " + mpm::cases().all().front().name + "; below)");
    app.add_option(
        "--mesh", o.mesh,
        "the background grid, tetrahedra: box:NX,NY,NZ[:refine=K] | file:PATH[:refine=K] (default box:16,16,16)");
    app.add_option(
        "--ordering", o.ordering,
        "the grid's element and node order, applied once: " + mpm::grid_orderings().accepted() + " (default natural)");
    app.add_option("--particles", o.particles,
                   "the particles' order: " + mpm::particle_orders().described() + " (default seeded)");
    app.add_option_function<std::string>(
           "--sort-every",
           [&o](const std::string& text) {
               o.sort_every = text == "auto"
                                  ? mpm::sort_auto
                                  : static_cast<int>(parse_whole(text, "--sort-every", 0, 1000000000, "or auto"));
           },
           "when sorted or dynamic particles are reordered: auto, whenever their order has decayed past "
           "--sort-threshold (the default; docs/mpm.md, \"When to reorder\"), or every K steps, 0: at the start only")
        ->type_name("auto|K");
    // Each particle order carries its own default (ParticleOrder::sort_threshold); named once where they agree.
    const double sorted_default = mpm::particle_orders().at("sorted").what.sort_threshold,
                 dynamic_default = mpm::particle_orders().at("dynamic").what.sort_threshold;
    app.add_option("--sort-threshold", o.sort_threshold,
                   "--sort-every=auto's threshold: the decay (the fall of the share of neighbours in one element, "
                   "summed over the steps since the last reordering) that a reordering costs, > 0 (default " +
                       (sorted_default == dynamic_default ? format_number(sorted_default)
                                                          : format_number(sorted_default) + " for sorted, " +
                                                                format_number(dynamic_default) + " for dynamic") +
                       ")");
    app.add_option("--renumber-share", o.renumber_share,
                   "dynamic under --sort-every=auto: a reordering renumbers the grid too when at least this share of "
                   "the particles lie outside the elements that held particles at the last renumbering, else it "
                   "sorts them alone; 0 to 1, 0: every time (default " +
                       format_number(mpm::default_renumber_share) + ")");
    app.add_option("--strategy", o.strategy,
                   "how threads share the scatters to nodes: " + mpm::strategies().accepted() +
                       " (default serial for 1 thread, partition for more)");
    add_whole_option(app, "--threads,-t", o.threads, 1, 1024, "OpenMP threads, 1 to 1024 (default 1)");
    add_whole_option(app, "--ppe", o.ppe, 1, 1000,
                     "particles seeded in each element of the column, 1 to 1000 (default 4)");
    app.add_option("--young", o.young,
                   "Young's modulus E in Pa, > 0 (elastic cases; default the case's: 1e5, free-fall 1e7)");
    app.add_option("--poisson", o.poisson, "Poisson's ratio ν, in (-1, 0.5) (elastic cases; default 0.3)");
    app.add_option(
        "--sound-speed", o.sound_speed,
        "the fluid's sound speed c in m/s, > 0: bulk modulus ρ c² (dam-break; default 35, 8 times the fastest flow)");
    app.add_option("--viscosity", o.viscosity,
                   "the fluid's dynamic viscosity η in Pa s, >= 0 (dam-break; default 1e-3, water)");
    app.add_option("--density", o.density, "density ρ in kg/m³, > 0 (default 1000)");
    app.add_option("--column", o.column,
                   "X,Y,Z: the material fills [0,X]x[0,Y]x[0,Z], inside the box (dam-collapse: default 0.4,0.4,0.8; "
                   "column: 1,1,0.5)");
    app.add_option("--courant", o.courant, "dt as a fraction of the stable step, in (0, 1] (default 0.8)");
    app.add_option("--integration", o.integration,
                   "how P2G integrates the stress: " + mpm::integrations().described() + " (default mixed)");
    app.add_option(
        "--damping", o.damping,
        "c in 1/s: a nodal force -c m v that brings the material to rest, for a quasi-static answer (default 0: none)");
    app.add_option("--dt", o.dt, "the time step in s, at most the stable one; 0: from --courant (default 0)");
    app.add_flag("--force", o.force, "run a dt or Courant number above the stable step anyway");
    app.add_option("--integrator", o.integrator, mpm::integrators().described() + " (elastic cases; default explicit)");
    app.add_option("--solver", o.solver,
                   "the implicit linear solve: " + mpm::linear_solvers().described() + " (default cg)");
    app.add_option("--newmark", o.newmark,
                   "BETA,GAMMA with 1/2 <= GAMMA <= 2 BETA <= 1 (implicit; default 0.25,0.5, average acceleration)");
    add_whole_option(
        app, "--newton-max", o.newton_max, 1, 1000,
        "Newton iterations a step may take, 1 to 1000; beyond it the run stops with status 3 (implicit; default 25)");
    app.add_option("--strain", o.strain,
                   "the implicit step's strain: " + mpm::strains().described() + " (default large)");
    add_seed_option(
        app, o.seed,
        "seed of the random grid ordering and the particles' shuffle, 0 to 18446744073709551615 (default 1)");
    add_whole_option(app, "--steps", o.steps, 0, 1000000000, "time steps, 0 to 10^9 (default 1000)");
    add_whole_option(app, "--warm-steps", o.warm_steps, 0, 1000000000,
                     "steps before the measured rate starts (the mixed state of a flow); the whole run's rate is "
                     "reported too (default 0)");
    add_whole_option(app, "--vtk-every", o.vtk_every, 0, 1000000000,
                     "steps between particle snapshots; 0: none (default 50)");
    app.add_option("--out,-o", o.out,
                   "directory for the snapshots, front.csv, mpm.json and front.png (created if missing; required "
                   "unless --dry-run)");
    app.add_flag("--no-png", o.no_png, "do not draw front.png");
    app.add_flag("--replace", o.replace, "replace the files of an earlier run in --out (refused without it)");
    app.add_flag("--dry-run", o.dry_run,
                 "check everything (the grid and particles are built), say what would run, write nothing");
    app.add_flag("--quiet,-q", o.quiet, "no progress line and no summary on the console");
}

}  // namespace suite::mpm_command
