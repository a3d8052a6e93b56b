#include "kernels/mpm/choices.hpp"

namespace suite::mpm {

namespace {

Settings case_base() {
    Settings s;
    s.integration = Integration::mixed;
    return s;
}

Settings with_region(Settings s, Region r) {
    s.region = r;
    return s;
}

Settings with_young(Settings s, double young) {
    s.material.young = young;
    return s;
}

Settings fluid(Settings s) {
    s.material.model = Material::Model::fluid;
    return s;
}

}  // namespace

const ChoiceTable<Case>& cases() {
    static const ChoiceTable<Case> table{
        "case",
        {{"dam-collapse",
          "an elastic column [0,0.4]x[0,0.4]x[0,0.8] in the corner (E = 1e5 Pa, nu = 0.3): it sags and rocks",
          {case_base(), Reference::none, ColumnOption::corner}},
         {"dam-break",
          "water [0,0.3]x[0,1]x[0,0.6] against the x = 0 wall (c = 35 m/s, eta = 1e-3 Pa s): it runs along the "
          "floor, hits the far wall and mixes",
          {with_region(fluid(case_base()), {{0, 0, 0}, {0.3, 1, 0.6}}), Reference::none, ColumnOption::none}},
         {"column",
          "an elastic layer [0,1]x[0,1]x[0,0.5] filling the box's width: the one-dimensional settlement "
          "rho g H^2 / (2 M) at its top",
          {with_region(case_base(), {{0, 0, 0}, {1, 1, 0.5}}), Reference::settlement, ColumnOption::full_width}},
         {"free-fall",
          "a stiff elastic block [0.3,0.7]x[0.3,0.7]x[0.5,0.9] (E = 1e7 Pa) away from the walls, falling from rest: "
          "until a wall acts every particle follows the explicit step's exact fall, within g t dt / 2 of "
          "z0 - g t^2 / 2; then it lands and bounces",
          // Stiff, so that the landing at 3 m/s strains it by about v / c = 3 % (26 % at E = 1e5 Pa,
          // where the energy check stopped runs on box:8, 16 and 32 after the landing).
          {with_region(with_young(case_base(), 1e7), {{0.3, 0.3, 0.5}, {0.7, 0.7, 0.9}}), Reference::free_fall,
           ColumnOption::none}}}};
    return table;
}

std::string elastic_cases() {
    std::vector<std::string> out;
    for (const auto& c : cases().all())
        if (!c.what.fluid()) out.push_back(c.name);
    return join(out, ", ");
}

const std::vector<std::string>& case_order_v1() {
    static const std::vector<std::string> order{"dam-collapse", "dam-break", "column"};
    return order;
}

const ChoiceTable<ParticleOrder>& particle_orders() {
    static const ChoiceTable<ParticleOrder> table{
        "particle order",
        {{"seeded", "as seeded, element by element in the grid's order, never reordered", {}},
         {"shuffled", "shuffled once, never reordered: a restart file's order", {.shuffle = true}},
         {"sorted",
          "sorted by element at the start and again as --sort-every says (default auto: when the order has "
          "decayed)",
          {.sorts = true}},  // the threshold default_sort_threshold (mpm.hpp)
         {"dynamic",
          "sorted as sorted is, and the grid renumbered active elements first at the start and when the particles "
          "have left its active elements",
          {.sorts = true, .renumbers = true}}},
        {{"unsorted", "shuffled"}}};
    return table;
}

const ChoiceTable<Strategy>& strategies() {
    static const ChoiceTable<Strategy> table{
        "strategy",
        {{"serial", "one thread, particles in order", Strategy::serial},
         {"atomic", "static blocks of particles, every node update an atomic add", Strategy::atomic},
         {"colour", "elements coloured so that no two of one colour share a node", Strategy::colour},
         {"partition", "one run of elements a thread, shared nodes into per-thread slots", Strategy::partition}}};
    return table;
}

const ChoiceTable<Integrator>& integrators() {
    static const ChoiceTable<Integrator> table{
        "integrator",
        {{"explicit", "USL", Integrator::explicit_step},
         {"implicit", "Newmark and Newton, any --dt; default 10x the stable step", Integrator::implicit},
         {"static", "each step an equilibrium", Integrator::quasi_static}}};
    return table;
}

const ChoiceTable<LinearSolver>& linear_solvers() {
    static const ChoiceTable<LinearSolver> table{
        "linear solver",
        {{"cg", "own, Jacobi-preconditioned", LinearSolver::cg}, {"cholmod", "SuiteSparse", LinearSolver::cholmod}}};
    return table;
}

const ChoiceTable<Integration>& integrations() {
    static const ChoiceTable<Integration> table{
        "integration",
        {{"mixed", "an element inside the material over its own volume, as Anura3D", Integration::mixed},
         {"particle", "over its particles alone, the grid-crossing error; see docs/mpm.md", Integration::particle}}};
    return table;
}

const ChoiceTable<bool>& strains() {
    static const ChoiceTable<bool> table{
        "--strain", {{"large", "Green-Lagrange, geometric stiffness", true}, {"small", "linear", false}}};
    return table;
}

const ChoiceTable<sfc::Ordering>& grid_orderings() {
    static const ChoiceTable<sfc::Ordering> table = sfc::distinct_orderings().subset(
        [](const sfc::Ordering& o) { return !(o.how == sfc::Ordering::How::sorted && o.method == sfc::Method::rcm); });
    return table;
}

}  // namespace suite::mpm
