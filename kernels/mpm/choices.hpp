#pragma once
// The MPM's named choices, each one table (harness/common/choice_table.hpp) declaring its names,
// help lines and behaviour once: `suite mpm`'s options and --help, the kernels' --case, variants
// and notes, and the records all read them. Adding a case is an entry in cases() and its physics.
#include <stdexcept>
#include <string>
#include <vector>

#include "harness/common/choice_table.hpp"
#include "kernels/mpm/mpm.hpp"
#include "kernels/sfc/orderings.hpp"

namespace suite::mpm {

// What a run of a case is checked against at its end (simulation.hpp), beyond the checks of every run.
enum class Reference {
    none,        // the checks of every run alone (and a fluid's Ritter front)
    settlement,  // the column: the one-dimensional settlement rho g H^2 / (2 M) at its top
    free_fall,   // the block's exact fall before it touches a wall (simulation.hpp, free_fall)
};
// Which --column a case takes: any box in the corner [0,X]x[0,Y]x[0,Z], a layer that fills the
// box's width (--column=1,1,Z: the one-dimensional answer needs it), or none (the region is the case's).
enum class ColumnOption { corner, full_width, none };

struct Case {
    Settings settings;  // material and region; the rest as Settings has them, mixed integration
    Reference reference = Reference::none;
    ColumnOption column = ColumnOption::corner;
    bool fluid() const { return settings.material.model == Material::Model::fluid; }
};
const ChoiceTable<Case>& cases();
// "dam-collapse, column, ...": the cases of the elastic material (what the implicit integrators take).
std::string elastic_cases();
// The cases in the order schema-1 records stored them as --case's index (result_file.cpp reads an
// old file through it): frozen, never reordered or extended.
const std::vector<std::string>& case_order_v1();

// How the particles are kept in order (Setup::particles).
struct ParticleOrder {
    bool shuffle = false;    // shuffled once at the start
    bool sorts = false;      // sorted by element (the grid's order) at the start and as Setup::sort_every says
    bool renumbers = false;  // and the grid renumbered, active elements first, at the same steps
    // --sort-every=auto's threshold where --sort-threshold is not given: the decay a reordering
    // costs (docs/mpm.md, "When to reorder"), measured for each order.
    double sort_threshold = default_sort_threshold;
};
const ChoiceTable<ParticleOrder>& particle_orders();

const ChoiceTable<Strategy>& strategies();
const ChoiceTable<Integrator>& integrators();
const ChoiceTable<LinearSolver>& linear_solvers();
const ChoiceTable<Integration>& integrations();
const ChoiceTable<bool>& strains();  // large (true) or small (false) strain in an implicit step
// The grid orderings an MPM grid takes: the mesh orderings' (kernels/sfc/orderings.hpp) that give
// an order of their own, less RCM, which no MPM kernel has been verified under.
const ChoiceTable<sfc::Ordering>& grid_orderings();

// The name of `what` in `table` (tables whose behaviour is an enum).
template <class B>
const std::string& name_of(const ChoiceTable<B>& table, B what) {
    for (const auto& c : table.all())
        if (c.what == what) return c.name;
    throw std::logic_error(table.what() + ": a value without a name");
}

}  // namespace suite::mpm
