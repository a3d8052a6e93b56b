#pragma once
// Explicit Material Point Method on an unstructured tetrahedral background grid, update stress
// last (USL), linear shape functions. Two materials: linear elastic with the Jaumann stress rate,
// and a weakly compressible Newtonian fluid (the pressure from the volume ratio, no tension).
// One step (step.cpp):
//   locate    every particle's element (a walk through face neighbours from its last one) and
//             its four shape function values w[i] = N_i(x_p), kept for the whole step
//   P2G       m_n += w m_p,  p_n += w m_p v_p,  f_n += w m_p g - V_p σ_p ∇N_i
//             (mixed integration: V_p scaled by |e| / Σ_{q in e} V_q in an element inside the material)
//   grid      p_n += dt (f_n - c p_n) (c: the damping, 0 unless asked for); the normal
//             components of p_n and f_n zeroed on the box's faces
//   G2P       v_p += dt Σ w f_n / m_n,  x_p += dt Σ w p_n / m_n
//   velocity  q_n = Σ w m_p v_p (a second scatter), v_n = q_n / m_n, walls again
//   stress    ∇v = Σ v_n ⊗ ∇N_i;  Δε, Δω its symmetric and skew parts times dt;
//             V_p *= 1 + tr(Δε), then
//               elastic: σ += λ tr(Δε) I + 2μ Δε + Δω σ - σ Δω
//               fluid:   σ = -p I + 2η dev(Δε / dt),  p = max(0, K (V0/V_p - 1)),  K = ρ0 c²,
//                        V0 = m_p / ρ0 (the volume at rest: no stress history to carry)
//   dt        fixed (elastic), or before every step courant · l / (c + max |v_p|) (fluid),
//             and at most courant · ρ0 l² / (6 η) (the viscous limit)
// The grid then returns to its original configuration (nodes are zeroed at the next step).
// Nothing here prints, reads a clock or allocates inside a step.
#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "kernels/mesh/mesh.hpp"
#include "kernels/mesh/mesh_spec.hpp"
#include "kernels/mpm/array.hpp"
#include "kernels/mpm/implicit_system.hpp"
#include "kernels/mpm/order.hpp"
#include "kernels/sfc/orderings.hpp"

namespace suite {
class Arena;
}

namespace suite::mpm {

struct State;

struct Material {
    enum class Model { elastic, fluid };
    Model model = Model::elastic;
    double young = 1e5;       // E, Pa (elastic)
    double poisson = 0.3;     // ν (elastic)
    double density = 1000;    // ρ (at rest, for the fluid), kg/m³
    double sound_speed = 35;  // c, m/s (fluid): the bulk modulus K = ρ c²
    double viscosity = 1e-3;  // η, Pa s (fluid; water's at 20 °C)
    // The speed of the pressure wave: sqrt(E (1 - ν) / ((1 + ν)(1 - 2ν) ρ)) (elastic), c (fluid), m/s.
    double wave_speed() const;
    double bulk_modulus() const { return density * sound_speed * sound_speed; }
};

// What one node accumulates in a step: one cache line, so that a scatter to a corner touches
// one line. p holds the momentum, then (after G2P) the second scatter's q.
struct alignas(64) NodeState {
    double m;
    double p[3];
    double f[3];
    double pad;
};

// The background grid: the box mesh with, per element, the coefficients of its four linear
// shape functions N_i(x) = a_i + g_i · x (shape[16 e + 4 i + {0,1,2,3}] = a_i, gx, gy, gz), the
// element across the face opposite each corner (-1 on the boundary), and per node which faces
// of the box it lies on (bit 0: x, 1: y, 2: z). All of it is rebuilt by permute().
struct Grid {
    mesh::Mesh mesh;                              // tetrahedra, corners in conn
    std::vector<double> shape;                    // 16 per element
    std::vector<std::int32_t> neighbour;          // 4 per element
    std::vector<std::uint8_t> wall;               // per node
    std::vector<std::uint32_t> curve;             // per element: its position along the Hilbert curve
    double lo[3] = {0, 0, 0}, hi[3] = {1, 1, 1};  // the box
    double min_length = 0;                        // smallest altitude of any element (the time step's l)

    std::size_t nodes() const { return mesh.vertices(); }
    std::size_t elements() const { return mesh.elements(); }
};

// Builds the grid of a tetrahedral mesh of a box (any ordering of it). Throws UsageError for a
// mesh that is not tetrahedral or has an inverted or flat element.
Grid make_grid(mesh::Mesh m);

// Scratch that a copy does not take (a copy starts without it, and makes its own if it needs it).
struct ReorderScratch {
    Array<double> buf;
    ReorderScratch() = default;
    ReorderScratch(const ReorderScratch&) {}
    ReorderScratch& operator=(const ReorderScratch&) { return *this; }
    ReorderScratch(ReorderScratch&&) = default;
    ReorderScratch& operator=(ReorderScratch&&) = default;
};

// Structure of arrays, one entry per particle. stress: xx, yy, zz, xy, yz, zx. Each array is
// either the State's own memory or placed in a kernel's Arena (array.hpp); the loops see raw
// pointers either way.
struct Particles {
    Array<double> x, y, z, vx, vy, vz, mass, volume;
    std::array<Array<double>, 6> stress;
    Array<double> w;            // 4 per particle: N_i at x_p in its element
    Array<std::uint32_t> elem;  // containing element
    Array<std::uint32_t>
        id;  // rank of its position at creation (any grid order gives the same ids); kept through sorting
    std::array<Array<double>, 3> accel;  // the implicit integrator's a_p (implicit.hpp); empty for the others
    // Placed particles only: 4 doubles per particle, where reorder_particles gathers before it
    // writes back (thread t's part is the 32 B per particle of its own block).
    ReorderScratch scratch;
    std::size_t size() const { return x.size(); }
    void resize(std::size_t n);  // own memory (a placed array keeps its length)
    // `n` particles in `arena` (the length fixed from then on), named as the record lists them
    // (particle_array_names, then "reorder-scratch"), each first touched by the particle loops'
    // static split (blocks.hpp: thread t writes the zeros of particles [lo, hi), of w and the
    // scratch [4 lo, 4 hi)), so that a thread's block lies where the policy puts it for that
    // thread. The values are zero; make_state seeds them.
    void place(std::size_t n, Arena& arena);
    bool placed() const { return x.placed(); }
    // The implicit integrators' accelerations, zero: in `arena` ("ax", "ay", "az", touched as
    // place() touches), or own memory without one.
    void add_accelerations(Arena* arena);
};
// The names of the placed particle arrays in the record's placement.arrays, in the order they
// are allocated; then "reorder-scratch".
inline constexpr const char* particle_array_names[] = {
    "x",         "y",         "z",         "vx",        "vy",        "vz", "mass", "volume", "stress-xx",
    "stress-yy", "stress-zz", "stress-xy", "stress-yz", "stress-zx", "w",  "elem", "id"};

// The material's region: the axis-aligned box [lo, hi]. dam-collapse puts it in the corner at
// the origin; tests put it elsewhere (free fall away from the walls).
struct Region {
    double lo[3] = {0, 0, 0};
    double hi[3] = {0.4, 0.4, 0.8};
};

// How P2G integrates the stress divergence over an element.
//   particle  Σ_p V_p σ_p ∇N_i over the element's particles: the volume the element sees jumps
//             whenever a particle crosses a face, the grid-crossing error that keeps linear MPM
//             from converging under refinement (docs/mpm.md, "The column")
//   mixed     as Anura3D's mixed integration: an element that holds particles and whose four
//             face neighbours do too (or are the box's walls) is integrated over its own volume,
//             |e| σ̄_e ∇N_i with σ̄_e the volume-weighted mean of its particles' stress; an element
//             at the material's surface keeps the particle sum
enum class Integration { particle, mixed };

struct Settings {
    Material material;
    Integration integration =
        Integration::particle;  // a bare Settings; case_settings (suite mpm, the kernels) take mixed
    Region region;
    int per_element = 4;  // particles in each element whose centroid lies in the region
    double gravity[3] = {0, 0, -9.81};
    double damping = 0;    // c, 1/s: a nodal force -c m_n v_n (mass-proportional), for a quasi-static answer; 0: none
    double courant = 0.8;  // dt = courant * min_length / wave_speed, unless dt is given
    double dt = 0;         // 0: from the Courant number (for a fluid, again before every step)
    Integrator integrator = Integrator::explicit_step;  // implicit and static: implicit.hpp (elastic only)
    ImplicitSettings implicit;
};

// The settings of a case that `suite mpm --case` and the kernels' `--case` run (choices.hpp, cases()):
// material and region. Throws UsageError for an unknown name.
Settings case_settings(const std::string& name);

// The stable time step of a grid and material at rest: min_length / wave_speed (Courant number 1),
// for a fluid also at most ρ0 l² / (6 η).
double critical_step(const Grid& g, const Material& m);
// The step a state takes next: the settings' dt when given; else the Courant number times the
// stable step, for a fluid with l / (c + the largest particle speed) in place of l / c.
double next_step(const State& st);

// How the threads share the scatters to nodes (P2G and the velocity scatter).
//   serial     one thread, particles in order
//   atomic     particles in static blocks, every node update an atomic add
//   colour     elements coloured so that no two of one colour share a node; one colour at a
//              time, its elements' particles (through the bins) added without synchronisation
//   partition  the elements in order split into one contiguous run per thread, balanced by
//              particles; nodes of one thread's run added directly, nodes two runs share
//              added into per-thread slots and reduced
enum class Strategy { serial, atomic, colour, partition };
Strategy parse_strategy(const std::string& name);  // throws UsageError (choices.hpp, strategies())
const char* strategy_name(Strategy s);

// Particles grouped by element: the particles of element e are order[start[e] .. start[e + 1]).
// Built by a counting sort after every locate (the colour and partition strategies use it).
struct Bins {
    std::vector<std::uint32_t> start;  // elements + 1
    Array<std::uint32_t> order;        // particles (placed with them: a per-particle array the scatters read)
    std::vector<std::uint32_t> next;   // scratch of the counting sort (elements)
};

// What a scatter strategy needs beyond the grid: the colouring (colour strategy), per-thread
// scratch (partition). Built once for a grid (again after permute) by plan_scatter().
struct ScatterPlan {
    Strategy strategy = Strategy::serial;
    int threads = 1;
    std::vector<std::uint32_t> colour_start;  // colours + 1: elements of colour c are colour_elems[colour_start[c] ..)
    std::vector<std::uint32_t> colour_elems;
    // partition scratch: per node the mask of threads touching it, per shared node its slot
    std::vector<std::uint64_t> touched;
    std::vector<std::int32_t> slot;
    std::vector<std::uint32_t> shared;     // the shared nodes, by slot
    std::vector<NodeState> slots;          // threads x shared
    std::vector<std::uint32_t> run_start;  // threads + 1: element runs
    // The updates of the last scatter that needed synchronisation: atomic adds to a node more
    // than one thread touched (atomic), additions into a shared slot (partition), 0 (colour).
    std::uint64_t synchronised = 0;
    std::uint64_t shared_nodes = 0;
    int colours() const { return colour_start.empty() ? 0 : static_cast<int>(colour_start.size()) - 1; }
};
ScatterPlan plan_scatter(const Grid& g, Strategy s, int threads);
// The colouring and the partition's per-node scratch (scatter_strategies.cpp).
void plan_colours(const Grid& g, ScatterPlan& plan);
void plan_partition(const Grid& g, ScatterPlan& plan);

// The state of a simulation. Built with an Arena (build(setup, &arena): the kernels), the
// particle arrays (with the bins' particle order, for the strategies that use bins), the nodes
// and the element volume sums are placed in it and first touched by the threads of the loops
// that compute on them; built without (suite mpm, the tests), they are the state's own memory,
// as is everything in a copy. What stays the state's own memory either way, first touched where
// it is built: the grid (shape functions, neighbours, connectivity, walls, curve), read-mostly
// and rebuilt by permute(), the connectivity inside the mesh::Mesh that sfc::permuted returns (a
// type the other mesh kernels share: placing it would mean an arena copy of the mesh kept in
// step with it); the bins' per-element counts; and the scatter plan (colours, the partition's
// per-node masks and slots), which permute() builds anew.
struct State {
    Grid grid;
    Particles particles;
    Array<NodeState> nodes;
    Bins bins;
    ScatterPlan plan;
    Settings settings;
    double dt = 0, time = 0;
    double dt_min = 0, dt_max = 0;  // the smallest and largest step taken (they differ for a fluid)
    std::uint64_t steps = 0;
    std::uint64_t clamped = 0;     // particle positions pulled back into the box, in total
    std::uint32_t node_hi = 0;     // 1 + the largest node any particle's element has
    Array<double> element_volume;  // mixed integration's scratch: Σ V_p of each element's particles
    OrderTracker order;            // the particles' reorderings (advance, reorder)
    ActiveSystem system;           // the implicit integrator's (implicit.hpp)
    ImplicitStats implicit;
};

// Places a located state's nodes (named "nodes") and, for mixed integration, element volume sums
// ("element-volume") in `arena`, first touched as their loops split them (touch_nodes; the
// elements by the static split of the zeroing loop). make_state calls it when given an arena,
// and before locating, for the colour and partition strategies, places the bins' particle order
// ("bins-order") as the particles are (Particles::place).
void place_grid_arrays(State& st, Arena& arena);
// Zeroes the nodes, thread t its static block of [0, node_hi) and then of [node_hi, nodes): the
// split of the loops over nodes (p2g's zeroing, update_grid, the nodal velocities). With
// `fresh`, placed nodes are first dropped (madvise MADV_DONTNEED), so that this is a new first
// touch: their pages land as the policy puts them for the threads that compute on them now,
// after the reorderings and motion since they were placed changed node_hi (a kernel does it at
// the end of its set-up, not between timed steps, where the drop and the page faults would be
// timed: a renumbering there keeps the nodes' pages, as it keeps the particles'). Own memory is
// only zeroed. The nodes' values are lost either way (p2g zeroes them before use).
void touch_nodes(State& st, bool fresh);

// A state at time 0: the grid, particles seeded in the region (per_element at fixed points of
// each element whose centroid lies inside it), located, at rest, unstressed. Throws UsageError
// for a region outside the box, per_element < 1, E <= 0, ν outside (-1, 0.5), ρ <= 0, or a
// given dt above the stable step (unless `force`).
// With `arena`, the particles, nodes and element volume sums are placed in it (State).
State make_state(Grid grid, const Settings& s, Strategy strategy, int threads, bool force = false,
                 Arena* arena = nullptr);

// The phases of a step, for the kernels that time one of them; step() runs them all.
void locate(State& st);  // elements and w of the particles at their current positions; bins
void p2g(State& st);     // zero the nodes, scatter m, p, f
void update_grid(State& st);
void g2p(State& st);
void update_stress(State& st);  // velocity scatter, nodal velocities, stress and volume
// p2g, update_grid, g2p, update_stress, then locate at the new positions: a state is always
// located between steps (make_state, sort_particles and renumber_active leave it so too).
void step(State& st);

// Reorders the particles by element number (a stable counting sort): afterwards the particles
// of one element are contiguous, in the grid's element order (the curve's on a curve-ordered
// grid, and after renumber_active). Keeps them located.
void sort_particles(State& st);
// The bins alone (colour and partition strategies; the others have none), from the particles'
// elements as they stand: what locate ends with, and all a permutation of located particles needs.
void bin_particles(State& st);
// The particles of a located state in order `order` (particle i of the result = particle
// order[i]), still located: each keeps its element and weights, so only the bins are rebuilt.
// Placed particles keep their storage: each thread gathers its static block of the result into
// its own part of the reorder scratch and, after a barrier, copies it back into the same block
// of the array, so every page stays where the policy and the first touch put it. Own memory is
// gathered into a new vector that takes the array's place.
void reorder_particles(State& st, const std::vector<std::uint32_t>& order);

// Renumbers the grid so that the elements holding particles come first, in curve order, then
// the others in their current order; nodes by first touch of that element order. Particles keep
// their positions; their elem is remapped. Rebuilds the scatter plan. Returns how many elements
// hold particles (the prefix they now fill).
std::uint32_t renumber_active(State& st);

// The grid with elements in order perm (element i of the result = element perm[i]) and node v
// renumbered new_id[v]; particle elements remapped through the inverse. The nodes are not
// permuted: p2g zeroes them before use.
void permute(State& st, const std::vector<std::uint32_t>& perm, const std::vector<std::uint32_t>& new_id);

// Setup::sort_every of --sort-every=auto.
inline constexpr int sort_auto = -1;
// --sort-every=auto's threshold (OrderTracker), from the cost model of docs/mpm.md ("When to
// reorder"): a sort costs as much as about this much decay, measured. Each particle order's own
// default is in its choice (ParticleOrder::sort_threshold); this is a bare Setup's, and both
// sorted's and dynamic's.
inline constexpr double default_sort_threshold = 1;
// dynamic under --sort-every=auto: a reordering the decay calls for renumbers the grid as well
// only when at least this share of the particles lie outside the elements that held particles at
// the last renumbering (OrderTracker::prefix); else it sorts them alone. Measured (docs/mpm.md,
// "When to reorder"); 0 renumbers at every reordering.
inline constexpr double default_renumber_share = 0.05;

// A simulation as the kernels and `suite mpm` set it up: which grid, in which order, how the
// particles are kept in order. build() loads the mesh, orders it once (the static reordering),
// seeds the particles and puts them in their starting order; advance() runs one step and the
// reorderings that fall due after it.
struct Setup {
    std::string mesh = "box:16,16,16";            // a --mesh spec of tetrahedra
    std::string ordering = sfc::as_given_name();  // of the grid: one of grid_orderings() (choices.hpp)
    // seeded:   as the seeding left them, element by element in the grid's order, never
    //           reordered: what a real code that seeds and never sorts has;
    // shuffled: shuffled once and never reordered (the worst case: a restart file's order);
    // sorted:   sorted by element, in the grid's order, at the start and as sort_every says;
    // dynamic:  sorted as above, and the grid renumbered (renumber_active) at the start, at every
    //           K steps, and under auto where renumber_share of the particles have left the
    //           elements of the last renumbering.
    std::string particles = "seeded";
    // Steps between reorderings; 0: at the start only; sort_auto (--sort-every=auto): whenever the
    // order has decayed past sort_threshold (OrderTracker).
    int sort_every = sort_auto;
    double sort_threshold = default_sort_threshold;
    double renumber_share = default_renumber_share;
    Settings settings;
    Strategy strategy = Strategy::serial;
    int threads = 1;
    std::uint64_t seed = 1;
    bool force = false;  // run a time step above the stable one
};
// Throws UsageError for a name that is not a particle order (choices.hpp), naming the old name's new one.
void check_particle_order(const std::string& name);
// The memory a State takes at its peak while it is built, from the grid's counts alone: the grid
// (shape functions, neighbours, keys), `particles` particles, and the mesh while it is loaded and
// ordered; `copies` of the grid and particles (a kernel's verify keeps a second); with `implicit`,
// the accelerations and a bound on the active system (implicit.hpp) too.
std::uint64_t state_bytes(const mesh::MeshCounts& c, std::uint64_t particles, int copies = 1, bool implicit = false);
// The most particles a setup can seed: per_element in every element of the region's share of a
// box grid (the unit cube), or of every element of a grid read from a file.
std::uint64_t particles_bound(const mesh::MeshSpec& spec, const mesh::MeshCounts& c, const Settings& s);
// Throws UsageError for a bad mesh spec, ordering, particle order or setting, and for a state
// larger than the memory available (estimated before anything is built).
// With `arena` (which must outlive the state), the state's particle and node arrays are placed
// in it (State): what the kernels do, so that the harness's --placement applies to them.
State build(const Setup& s, Arena* arena = nullptr);
// One step, then the reordering due after it: every sort_every steps, or under sort_auto when the
// decay accumulated since the last one (OrderTracker) has reached sort_threshold.
void advance(State& st, const Setup& s);
// Sorts the particles (dynamic: after renumbering the grid, unless the decay called for it and
// fewer than renumber_share of the particles are outside the last renumbering's elements), as a
// reordering of this setup's particle order, and restarts the tracker's decay from the order it
// leaves; logged with `cause`.
void reorder(State& st, const Setup& s, ReorderCause cause);
// "--sort-every=auto" or "--sort-every=K" (the value as a setup holds it).
std::string sort_every_text(int sort_every);

// Sums over particles, for the checks.
struct Totals {
    double mass = 0;
    double momentum[3] = {0, 0, 0};
    double kinetic = 0;
};
Totals totals(const Particles& p);
double front(const Particles& p);  // the largest x of any particle (the dam's front)

// The energy of a state: kinetic; potential, Σ m (-g)·x; internal: elastic, ½ V σ : ε with ε
// from σ through the isotropic compliance, or the fluid's Σ V0 K (J - 1 - ln J) for J = V/V0 < 1
// (the work its pressure stores; none in tension, which it does not take).
struct Energy {
    double kinetic = 0, potential = 0, internal = 0;
    double total() const { return kinetic + potential + internal; }
};
Energy energy(const State& st);

Locality locality(const State& st);
// The share of consecutive particles in one element alone (Locality::same_element), from the
// elements they are stored with: what --sort-every=auto reads after every step.
double same_element_share(const Particles& p);

}  // namespace suite::mpm
