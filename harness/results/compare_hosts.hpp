#pragma once
// `suite compare RUN.json` with one file of an MPI run (suite-mpi): the hosts of that run side
// by side, point by point, to find the slow node; on a single host, its ranks instead. It reads
// only the records; it never runs anything.
#include <string>

#include "harness/results/result_file.hpp"

namespace suite {

// Per point, one column per host (for a figure where higher is better, such as GB/s, the sum of
// the best figures of the host's ranks, which ran at once; where lower is better, such as
// ns/load, its worst rank's best), each host's performance relative to the fastest host, the
// slowest host named, the aggregate record and its rank spread; then the geometric mean of
// each host's ratios per kernel. On one host the columns are its ranks. Throws InputError for
// a file that is not of an MPI run of two ranks or more, or that has no rank record with a figure.
std::string render_host_comparison(const ResultFile& run, bool markdown);

}  // namespace suite
