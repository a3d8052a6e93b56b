#pragma once
// The particles' order as the MPM state tracks it: how far it is from the curve's (Locality), and
// its reorderings, when and why (OrderTracker), which --sort-every=auto reads (setup.cpp, advance).
#include <cstdint>
#include <vector>

namespace suite::mpm {

// How far the particles' order is from the curve's, read from the order they are stored in:
// the mean distance along the element curve (grid.curve) between consecutive particles'
// elements, and the share of consecutive particles in the same element. Sorted: a distance
// about 1 / (particles per element); shuffled: about a third of the elements.
struct Locality {
    double mean_gap = 0;      // elements along the curve
    double same_element = 0;  // 0..1
};

// Why the particles were reordered (and, dynamic, the grid renumbered).
//   start    at the start (build) or where a kernel's timing starts
//   every    K = --sort-every steps since the last one
//   decayed  --sort-every=auto: the order had decayed past the threshold (OrderTracker)
enum class ReorderCause { none, start, every, decayed };
const char* reorder_cause_name(ReorderCause c);  // "", "start", "every", "decayed"

struct Reordering {
    std::uint64_t step = 0;  // after this many steps of the state
    ReorderCause cause = ReorderCause::none;
    double decay = 0;        // the decay accumulated since the one before (OrderTracker::decay)
    double same_before = 0;  // same_element before it, and after it
    double same_after = 0;
    // dynamic: the share of particles in elements that held none at the last renumbering (numbered
    // from OrderTracker::prefix on) before it, and whether the grid was renumbered this time
    double outside = 0;
    bool renumbered = false;
};

// How far the order has decayed since the last reordering, in what --sort-every=auto reads: the
// share of consecutive particles in one element right after it (fresh), and the sum over the
// steps since of how far below that share the order has fallen (decay: a share times steps).
// The loss of a step grows with that fall; the sum is the loss accumulated since, in units of the
// loss a step with no particle next to one of its element would have. A reordering is due when
// it reaches the threshold, which stands for the reordering's own cost in the same units
// (Setup::sort_threshold). It reads the particles' elements alone, never a clock: a run's
// reorderings are the same every time, and a replay makes them again.
struct OrderTracker {
    double fresh = 0, decay = 0;
    std::uint64_t count = 0;      // reorderings since the state was built, the start's included
    std::vector<Reordering> log;  // the first log_limit of them
    static constexpr std::size_t log_limit = 100000;
    ReorderCause last_cause = ReorderCause::none;
    std::uint64_t last_step = 0;
    // dynamic particles: the elements numbered below prefix held particles at the last renumbering
    // (renumber_active puts them first); renumberings counts those since the state was built
    std::uint32_t prefix = 0;
    std::uint64_t renumberings = 0;
};

}  // namespace suite::mpm
