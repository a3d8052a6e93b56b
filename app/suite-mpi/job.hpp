#pragma once
// The MPI job as suite-mpi sees it: which rank this is, on which host, and which of that host's
// CPUs it was given. start_job() is collective: the ranks of each host share its CPUs out
// (machine/rank_share.hpp), each binds itself to its share, and every host's sets are checked
// for overlap before anything is measured; rank 0 gathers what every host is for the result's
// context.
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace suite {

struct Job {
    int rank = 0, size = 1;
    std::string host;
    std::vector<int> cpus;   // this rank's share, bound
    nlohmann::json context;  // rank 0: context.mpi (schema: library, ranks, layout, hosts); null elsewhere
    int hosts = 1;           // distinct hosts (every rank)
};

// Thrown on every rank when the job cannot start (a host with more ranks than cores, CPU sets
// that overlap): `message` is set on rank 0 only, which says it; the others end quietly.
struct JobRefused : std::exception {
    std::string message;
    const char* what() const noexcept override { return message.c_str(); }
};

Job start_job();

// Rank 0's `text` as every rank's, and whether rank 0 had one (a collective helper for the
// decisions that only rank 0 takes, such as claiming the output file).
std::string broadcast_text(const std::string& text);

// Every rank's `text`, in rank order, on rank 0 (empty elsewhere).
std::vector<std::string> gather_texts(const std::string& text);

}  // namespace suite
