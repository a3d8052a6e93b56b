#pragma once
// Explicit Material Point Method on an unstructured tetrahedral background grid, update stress
// last (USL), linear shape functions, linear elastic material with the Jaumann stress rate.
// One step (step.cpp):
//   locate    every particle's element (a walk through face neighbours from its last one) and
//             its four shape function values w[i] = N_i(x_p), kept for the whole step
//   P2G       m_n += w m_p,  p_n += w m_p v_p,  f_n += w m_p g - V_p σ_p ∇N_i
//   grid      p_n += dt f_n; the normal components of p_n and f_n zeroed on the box's faces
//   G2P       v_p += dt Σ w f_n / m_n,  x_p += dt Σ w p_n / m_n
//   velocity  q_n = Σ w m_p v_p (a second scatter), v_n = q_n / m_n, walls again
//   stress    ∇v = Σ v_n ⊗ ∇N_i;  Δε, Δω its symmetric and skew parts times dt;
//             σ += λ tr(Δε) I + 2μ Δε + Δω σ - σ Δω;  V_p *= 1 + tr(Δε)
// The grid then returns to its original configuration (nodes are zeroed at the next step).
// Nothing here prints, reads a clock or allocates inside a step.
#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "kernels/mesh/mesh.hpp"
#include "kernels/mesh/mesh_spec.hpp"

namespace suite::mpm {

struct Material {
    double young = 1e5;      // E, Pa
    double poisson = 0.3;    // ν
    double density = 1000;   // ρ, kg/m³
    // The speed of the pressure wave, sqrt(E (1 - ν) / ((1 + ν)(1 - 2ν) ρ)), m/s.
    double wave_speed() const;
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
    mesh::Mesh mesh;                      // tetrahedra, corners in conn
    std::vector<double> shape;            // 16 per element
    std::vector<std::int32_t> neighbour;  // 4 per element
    std::vector<std::uint8_t> wall;       // per node
    std::vector<std::uint32_t> curve;     // per element: its position along the Hilbert curve
    double lo[3] = {0, 0, 0}, hi[3] = {1, 1, 1};  // the box
    double min_length = 0;                // smallest altitude of any element (the time step's l)

    std::size_t nodes() const { return mesh.vertices(); }
    std::size_t elements() const { return mesh.elements(); }
};

// Builds the grid of a tetrahedral mesh of a box (any ordering of it). Throws UsageError for a
// mesh that is not tetrahedral or has an inverted or flat element.
Grid make_grid(mesh::Mesh m);

// Structure of arrays, one entry per particle. stress: xx, yy, zz, xy, yz, zx.
struct Particles {
    std::vector<double> x, y, z, vx, vy, vz, mass, volume;
    std::array<std::vector<double>, 6> stress;
    std::vector<double> w;              // 4 per particle: N_i at x_p in its element
    std::vector<std::uint32_t> elem;    // containing element
    std::vector<std::uint32_t> id;      // rank of its position at creation (any grid order gives the same ids); kept through sorting
    std::size_t size() const { return x.size(); }
    void resize(std::size_t n);
};

// The material's region: the axis-aligned box [lo, hi]. dam-collapse puts it in the corner at
// the origin; tests put it elsewhere (free fall away from the walls).
struct Region {
    double lo[3] = {0, 0, 0};
    double hi[3] = {0.4, 0.4, 0.8};
};

struct Settings {
    Material material;
    Region region;
    int per_element = 4;       // particles in each element whose centroid lies in the region
    double gravity[3] = {0, 0, -9.81};
    double courant = 0.8;      // dt = courant * min_length / wave_speed, unless dt is given
    double dt = 0;             // 0: from the Courant number
};

// The stable time step of a grid and material: min_length / wave_speed (Courant number 1).
double critical_step(const Grid& g, const Material& m);

// How the threads share the scatters to nodes (P2G and the velocity scatter).
//   serial     one thread, particles in order
//   atomic     particles in static blocks, every node update an atomic add
//   colour     elements coloured so that no two of one colour share a node; one colour at a
//              time, its elements' particles (through the bins) added without synchronisation
//   partition  the elements in order split into one contiguous run per thread, balanced by
//              particles; nodes of one thread's run added directly, nodes two runs share
//              added into per-thread slots and reduced
enum class Strategy { serial, atomic, colour, partition };
Strategy parse_strategy(const std::string& name);  // throws UsageError
const char* strategy_name(Strategy s);

// Particles grouped by element: the particles of element e are order[start[e] .. start[e + 1]).
// Built by a counting sort after every locate (the colour and partition strategies use it).
struct Bins {
    std::vector<std::uint32_t> start;  // elements + 1
    std::vector<std::uint32_t> order;  // particles
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
    std::vector<std::uint32_t> shared;                 // the shared nodes, by slot
    std::vector<NodeState> slots;                      // threads x shared
    std::vector<std::uint32_t> run_start;              // threads + 1: element runs
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

// The state of a simulation.
struct State {
    Grid grid;
    Particles particles;
    std::vector<NodeState> nodes;
    Bins bins;
    ScatterPlan plan;
    Settings settings;
    double dt = 0, time = 0;
    std::uint64_t steps = 0;
    std::uint64_t clamped = 0;         // particle positions pulled back into the box, in total
    std::uint32_t node_hi = 0;         // 1 + the largest node any particle's element has
};

// A state at time 0: the grid, particles seeded in the region (per_element at fixed points of
// each element whose centroid lies inside it), located, at rest, unstressed. Throws UsageError
// for a region outside the box, per_element < 1, E <= 0, ν outside (-1, 0.5), ρ <= 0, or a
// given dt above the stable step (unless `force`).
State make_state(Grid grid, const Settings& s, Strategy strategy, int threads, bool force = false);

// The phases of a step, for the kernels that time one of them; step() runs them all.
void locate(State& st);   // elements and w of the particles at their current positions; bins
void p2g(State& st);      // zero the nodes, scatter m, p, f
void update_grid(State& st);
void g2p(State& st);
void update_stress(State& st);  // velocity scatter, nodal velocities, stress and volume
// p2g, update_grid, g2p, update_stress, then locate at the new positions: a state is always
// located between steps (make_state, sort_particles and renumber_active leave it so too).
void step(State& st);

// Reorders the particles by their elements' positions along the curve (counting sort on
// grid.curve[elem]): afterwards the particles of one element are contiguous, elements in curve
// order. Keeps them located.
void sort_particles(State& st);
// The particles in order `order` (particle i of the result = particle order[i]), located again.
void reorder_particles(State& st, const std::vector<std::uint32_t>& order);

// Renumbers the grid so that the elements holding particles come first, in curve order, then
// the others in their current order; nodes by first touch of that element order. Particles keep
// their positions; their elem is remapped. Rebuilds the scatter plan.
void renumber_active(State& st);

// The grid with elements in order perm (element i of the result = element perm[i]) and node v
// renumbered new_id[v]; particle elements remapped through the inverse.
void permute(State& st, const std::vector<std::uint32_t>& perm, const std::vector<std::uint32_t>& new_id);

// A simulation as the kernels and `suite mpm` set it up: which grid, in which order, how the
// particles are kept in order. build() loads the mesh, orders it once (the static reordering),
// seeds the particles and puts them in their starting order; advance() runs one step and the
// reorderings that fall due after it.
struct Setup {
    std::string mesh = "box:16,16,16";  // a --mesh spec of tetrahedra
    std::string ordering = "natural";   // of the grid: natural, random, morton, hilbert
    // unsorted: the particles shuffled once (as a generator or a restart file may leave them)
    //           and never reordered;
    // sorted:   sorted along the curve at the start and every sort_every steps;
    // dynamic:  sorted as above, and the grid renumbered (renumber_active) at the same steps.
    std::string particles = "unsorted";
    int sort_every = 5;                 // steps between reorderings; 0: at the start only (5: fastest measured)
    Settings settings;
    Strategy strategy = Strategy::serial;
    int threads = 1;
    std::uint64_t seed = 1;
    bool force = false;                 // run a time step above the stable one
};
// The accepted names, for messages and --help.
inline constexpr const char* orderings_accepted = "natural, random, morton, hilbert";
inline constexpr const char* particle_orders_accepted = "unsorted, sorted, dynamic";
// The memory a State takes at its peak while it is built, from the grid's counts alone: the grid
// (shape functions, neighbours, keys), `particles` particles, and the mesh while it is loaded and
// ordered; `copies` of the grid and particles (a kernel's verify keeps a second).
std::uint64_t state_bytes(const mesh::MeshCounts& c, std::uint64_t particles, int copies = 1);
// The most particles a setup can seed: per_element in every element of the region's share of a
// box grid (the unit cube), or of every element of a grid read from a file.
std::uint64_t particles_bound(const mesh::MeshSpec& spec, const mesh::MeshCounts& c, const Settings& s);
// Throws UsageError for a bad mesh spec, ordering, particle order or setting, and for a state
// larger than the memory available (estimated before anything is built).
State build(const Setup& s);
void advance(State& st, const Setup& s);
// Whether advance() reorders after step number `step` (1-based) under this setup.
bool reorders_after(const Setup& s, std::uint64_t step);

// Sums over particles, for the checks.
struct Totals {
    double mass = 0;
    double momentum[3] = {0, 0, 0};
    double kinetic = 0;
};
Totals totals(const Particles& p);
double front(const Particles& p);  // the largest x of any particle (the dam's front)

}  // namespace suite::mpm
