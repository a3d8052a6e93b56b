#pragma once
// The contract between the harness and a kernel. A kernel allocates through the Arena and
// touches its memory first from the computing threads, runs one repetition per run() call,
// and checks its own answer in verify(). A Kernel never reads a clock, pins a thread or
// prints: the runner does all of that, at the same points for every kernel.
//
// Two kinds of kernel share this interface:
//  - streaming kernels (stream/): sized by their memory footprint in bytes, walking memory
//    in an access *pattern* (sequential, random, strided:S);
//  - application kernels (kernels/): sized by a count (mesh elements, particles), their data
//    laid out in an *ordering* (natural, random, morton, hilbert, rcm).
// KernelInfo says which; the CLI, runner and reports only look at that data.
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "harness/kernel/arena.hpp"
#include "harness/kernel/comm.hpp"
#include "harness/kernel/param_value.hpp"

namespace suite {

enum class AccessAxis { pattern, ordering };
enum class SizeKind { bytes, count };
enum class Metric { bandwidth, latency };

// One access pattern (harness/kernel/patterns.hpp) or data ordering, e.g. {"strided", 8} or {"morton", 0}.
struct Access {
    std::string name;
    std::uint64_t stride = 0;   // only for a pattern that takes one (strided)
    std::string label() const;  // "strided:8", "morton"
};

// Whether `v` is one of the variants --stores picks (store_variants.hpp), as opposed to the
// choices of a kernel's variant option.
bool is_store_variant(const std::string& v);

struct KernelConfig {
    Access access;
    std::string variant;  // "" for the plain kernel, a store variant (is_store_variant), or a variant option's choice
    std::uint64_t size = 0;  // footprint in bytes (SizeKind::bytes) or a count (SizeKind::count)
    std::uint64_t seed = 1;
    int threads = 1;
    std::string mesh = "";  // kernels on a mesh: the --mesh spec; "" = a generated mesh of about `size` elements
    // The values of the kernel's declared parameters (KernelInfo::params), defaults filled in.
    Params params = {};
    // The ranks of the run (comm.hpp): nullptr in a run of one process. A kernel that
    // distributes its work takes its share from communicator(); no other kernel looks.
    const Comm* comm = nullptr;
    const Comm& communicator() const { return comm ? *comm : single_process(); }
    // One of them: a number (param) or a named parameter's name (choice); a name the kernel did
    // not declare, a config built without them, or the other kind is a std::logic_error, not a
    // silent 0.
    double param(const std::string& name) const;
    const std::string& choice(const std::string& name) const;
};

// What one repetition does, counted once, from which the runner derives every rate.
struct Work {
    double units = 0;           // elements updated, loads chased, triangles assembled, ...
    double stream_bytes = 0;    // bytes by the STREAM convention (each array access once, 8 B a double)
    double hardware_bytes = 0;  // estimate of what the memory system moves (write-allocate, index
                                // arrays, whole 64 B lines for scattered accesses)
    double flops = 0;
    std::uint64_t footprint_bytes = 0;  // all of the kernel's arrays together
};

struct Verification {
    bool passed = false;
    std::string detail;    // what was checked, and the first mismatch if any
    double max_error = 0;  // largest |computed - expected| seen
    // An iterative solver did not converge: the record is not verified (the runner sets
    // passed = false too) and the run ends with exit status 3.
    bool solver_failed = false;
};

// A number a kernel reports about its last run, beside its timings: an eigenvalue, an iteration
// count, how many contributions were synchronised. Reported as is; no rate is derived from it.
struct Fact {
    std::string name;  // "lambda", "iterations", "cg-iterations"
    double value = 0;
    std::string unit;  // "" for a pure number
};

class Kernel {
public:
    virtual ~Kernel() = default;
    // Allocate through `arena` and initialise in parallel (OpenMP team already sized and pinned).
    virtual void setup(Arena& arena) = 0;
    // `calls` repetitions back to back inside one parallel region, so that short calls do not
    // measure fork and join. A thread starts its next call only when what that call reads is
    // complete: after a barrier where threads share data, at once where each thread touches
    // only its own block. All of them are done when run() returns. Never reads a clock.
    virtual void run(int calls) = 0;
    // Checks the state after any number of run() calls against the analytic answer.
    virtual Verification verify() = 0;
    // Work of one repetition; valid after setup().
    virtual Work work() const = 0;
    // Facts about the state verify() checked (read by the runner right after verify()).
    virtual std::vector<Fact> facts() const { return {}; }
};

// A value that configures a kernel, given on the command line as --NAME=X (e.g. --tol=1e-10).
// The harness parses it (a finite number, or one of a named parameter's names) and fills in the
// default; the kernel's `validate` checks its range.
struct ParamInfo {
    std::string name;  // lower case, digits and '-': "delta", "tol"
    double default_value = 0;
    std::string help;  // one line for --help and ./suite list
    // A named parameter (--case=dam-break) takes one of these names (a choice table's, in its
    // order), defaults to the first, and is recorded as the name; empty: a number.
    std::vector<std::string> choices = {};
    // The names in the order schema-1 records stored them as indices 0, 1, ... (frozen with that
    // schema: result_file.cpp reads an old file's index through it); empty where none were stored.
    std::vector<std::string> v1_order = {};
    // A named parameter that takes a number too (--sort-every=auto or 20): a name where one of
    // the choices is given, else a finite number; its default is still the first name.
    bool numbers_too = false;
};

// Facts about a kernel, as data.
struct KernelInfo {
    std::string name;     // "add", "sin-add", "latency", "fem-spmv"
    std::string group;    // "stream", "latency", "fem", ...
    std::string formula;  // the reference loop in one line
    std::string unit;     // what Work::units counts: "element", "load", "triangle"
    AccessAxis axis = AccessAxis::pattern;
    std::vector<std::string> accesses;  // patterns or orderings supported ("strided" stands for strided:S)
    std::vector<std::string> variants = {""};
    // The command-line option that picks variants other than "" and the store variants: "phase" (--phase, where
    // "all" names the plain kernel ""), "strategy" (--strategy), "particles" or "isa".
    std::string variant_option = "phase";
    // Names the variant option no longer accepts, each with the one that replaced it (a refusal
    // says "did you mean" the new one).
    std::vector<std::pair<std::string, std::string>> retired_variants = {};
    // The variants run when that option is not given; empty: the plain kernel "" alone.
    std::vector<std::string> default_variants;
    // The name the variant option gives the plain kernel "" where it is one of the choices
    // (--strategy=csr for fem-spmv: its records keep the kernel's own name); --phase always calls
    // it "all". Empty: the plain kernel is not named under the option.
    std::string plain_variant_name;
    // Variants that run on one thread only: left out of points with more threads when the
    // variants were defaulted, and refused with --threads above 1 when named.
    std::vector<std::string> single_thread_variants;
    std::vector<ParamInfo> params;
    SizeKind size_kind = SizeKind::bytes;
    // A kernel sized by a count and not on a mesh: its size when none is given (0: the
    // cache-level sizes, as for a footprint).
    std::uint64_t default_count = 0;
    Metric metric = Metric::bandwidth;
    // STREAM-convention bytes and flops per unit, as documentation (Work is authoritative).
    double read_bytes_per_unit = 0;
    double write_bytes_per_unit = 0;
    double flops_per_unit = 0;
    std::string notes;
    // Its arrays are ordinary heap memory, not Arena arrays (no kernel of the suite, now that the
    // MPM kernels' are the arena's): the harness cannot place them, so a --placement other than
    // local is refused for it.
    bool heap_arrays = false;
};

using KernelFactory = std::function<std::unique_ptr<Kernel>(const KernelConfig&)>;

struct KernelEntry {
    KernelInfo info;
    KernelFactory make;
    // Throws UsageError for a configuration the kernel cannot run (too small, too large, a
    // variant that does not fit the pattern); called for every point before anything runs.
    std::function<void(const KernelConfig&)> validate = [](const KernelConfig&) {};
    // A size at which the kernel runs in milliseconds, for the registry walk.
    std::uint64_t test_size = 64 << 10;
    // Kernels on a mesh (null for the others): the element count of a --mesh spec, which is the
    // point's size (throws UsageError for a bad spec or mesh file), and the meshes a run uses
    // when neither --mesh nor a size is given.
    std::function<std::uint64_t(const std::string& spec)> mesh_elements;
    std::vector<std::string> default_meshes;
};

// The registry: kernels add themselves from their own .cpp with
//   static const bool registered = register_kernel({...});
// It throws std::logic_error for a name given twice or facts that do not fit together (a default
// or single-thread variant not among the variants, an unknown variant_option, a parameter named
// twice or not in lower case).
bool register_kernel(KernelEntry entry);
const std::vector<KernelEntry>& kernels();
const KernelEntry* find_kernel(const std::string& name);
std::vector<std::string> kernel_names();
// Every declared parameter of `info` at its default value.
Params default_params(const KernelInfo& info);
// --NAME=TEXT as the value a parameter keeps: a finite number, or one of a named parameter's names
// (ParamInfo::choices). Throws UsageError for anything else, naming what is accepted.
ParamValue parse_param(const std::string& name, const std::string& text);
// Whether `variant` of `info` runs on one thread only (KernelInfo::single_thread_variants).
bool single_thread_only(const KernelInfo& info, const std::string& variant);

// Throws std::runtime_error when an OpenMP team came out with `got` threads where `asked` were
// asked for (bind_team, and the kernels' parallel first touch, check their team with it).
void require_team_size(int got, int asked);

}  // namespace suite
