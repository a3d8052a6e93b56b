#pragma once
// Where the OpenMP threads run. A PinSpec turns into an ordered list of PUs; bind_team() pins
// thread k of a team to the k-th PU of that list and then reads back, from the OS, what each
// thread really got, because a binding that was asked for is not evidence that it held.
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "harness/common/choice_table.hpp"
#include "harness/machine/topology.hpp"

namespace suite {

enum class PinMode { none, compact, scatter, list };

struct PinSpec {
    PinMode mode = PinMode::compact;
    std::vector<int> cpus;  // for PinMode::list: OS indexes in thread order
    std::string text;       // as given, for the record
};

// --pin's named modes (compact, scatter, none), one table: parse_pin, its messages and --help read
// it. A CPU list (PinMode::list) is the one form that is not a name.
const ChoiceTable<PinMode>& pin_modes();

// The name of a named mode in pin_modes(); a logic error for PinMode::list.
const std::string& pin_name(PinMode m);

// The forms --pin accepts, for messages and --help: "compact, scatter, none, or a CPU list such as 0,2,4-7".
std::string pin_forms();

// A name of pin_modes() or a CPU list such as "0,2,4-7". Throws UsageError.
PinSpec parse_pin(std::string_view text, const Topology& topo);

// The order in which threads take PUs (OS indexes), empty for PinMode::none.
//  compact: one PU per core, cores in hwloc's logical order (filling package 0, then 1, ...),
//           then the second hyperthread of every core, and so on;
//  scatter: one PU per core, taking cores round-robin over the NUMA nodes (so 2 threads on a
//           2-socket machine land on different sockets), then the hyperthreads the same way;
//  list:    exactly the CPUs given.
std::vector<int> pin_order(const Topology& topo, const PinSpec& spec);

struct ThreadBinding {
    int thread = 0;
    int requested_cpu = -1;    // -1: not pinned
    std::vector<int> allowed;  // the CPU set the OS reports for the thread after binding
    int cpu = -1;              // where it was running when read back
    int numa_node = -1;        // the NUMA node of `cpu`
};

// Sets the OpenMP team size to `threads`, pins each thread (or, for PinMode::none, restores the
// process's original CPU set) and returns what each thread reports. Throws std::runtime_error
// when the OS refuses a binding.
std::vector<ThreadBinding> bind_team(const Topology& topo, const PinSpec& spec, int threads);

// Whether every thread of the current OpenMP team of team.size() threads still has the CPU set
// bind_team() read back: run after the timed repetitions, it shows that the kernels ran on the
// pinned threads (and not on threads the OpenMP runtime created afterwards).
bool team_still_bound(const std::vector<ThreadBinding>& team);

// The calling thread's CPU affinity, as OS CPU numbers.
std::vector<int> current_cpuset();

nlohmann::json to_json(const ThreadBinding& b);

}  // namespace suite
