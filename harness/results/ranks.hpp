#pragma once
// The aggregate of one point measured by every rank of an MPI run at once (suite-mpi), as
// STREAM's MPI version reports it: the ranks' work added up over, repetition by repetition, the
// time of the slowest rank (the ranks start each repetition together, so the slowest one's time
// is the wall time of the whole job's repetition). No MPI here: the per-rank records arrive as
// the JSON that to_json(Record) wrote on each rank.
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "harness/measure/result.hpp"

namespace suite {

// What the aggregate needs of one rank's record.
struct RankRun {
    int rank = 0;
    std::string host;
    int threads = 0;
    std::vector<double> samples_s;  // per call, one per counted repetition
    Work work;
    bool passed = false, solver_failed = false, held = false, unstable = false;
    std::string detail, unstable_why;
    double max_error = 0;
    std::vector<ThreadBinding> bindings;  // its threads, as it pinned and read them back
};

// From a record as to_json(Record) renders it, with its "mpi" block (scope rank). Throws
// std::runtime_error naming the field when one is missing (a rank running another build).
RankRun rank_run_from_json(const nlohmann::json& record);

// The aggregate record of `ranks` (every rank of the run, in rank order; the same repetitions
// each), built on `first` (rank 0's own record: the point's kernel, access, size, parameters).
// threads and work are the sums, the thread bindings every rank's in rank order (numbered on); per repetition the
// longest of the ranks' times; verified when every rank verified; counters and energy stay in the rank records (the
// ranks of one host share its packages: a sum would count them twice), so here they say where to look.
Record aggregate_record(const Record& first, const std::vector<RankRun>& ranks, int hosts);

}  // namespace suite
