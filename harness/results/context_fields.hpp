#pragma once
// The context of a loaded result file as a reader compares machines: each field that changes
// what a benchmark measures, as display text, and the fields on which several files disagree.
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "harness/results/result_file.hpp"

namespace suite {

// A context field as text for display ("?" when absent or of an unexpected type): "cpu_model",
// "caches" (a summary of topology.caches), "transparent_hugepages", "frequency_governor", ...
std::string context_text(const nlohmann::json& context, const std::string& field);
// A record's instruction_set in words: "AVX-512", "AVX2", "SSE2" (x86-64), "NEON", "SVE 256-bit" (aarch64).
std::string instruction_set_text(const nlohmann::json& instruction_set);

// The context fields whose differences change what a benchmark measures, in display order.
const std::vector<std::string>& context_fields_that_matter();

// For each field of context_fields_that_matter() on which the files disagree: the field and
// each file's value, in the order of `files`; then "hugepages" (what the records asked of huge
// pages, e.g. "none" against "thp") where the files' records disagree on it, and "mpi" (one
// process, or MPI ranks and which host each ran on) where the runs' processes differ.
std::vector<std::pair<std::string, std::vector<std::string>>> context_differences(
    const std::vector<const ResultFile*>& files);

// What a context field says: what the machine is (its CPU, cores, memory: compare's subject,
// and a gate's baseline must share them), how the run was built and set up (compiler, flags,
// the instruction set -march resolved to, huge pages: a difference changes every result), or a fact worth listing that
// varies without changing what a point means (the reported caches on a VM that moves between hosts, the frequency
// governor).
enum class FieldKind { machine, setting, informational };
FieldKind context_field_kind(const std::string& field);
// The same for these files: what -march=native resolved to (instruction_set) is the machine's
// where every file was built with -march=native (the user chose "this machine's", not an ISA).
FieldKind context_field_kind(const std::string& field, const std::vector<const ResultFile*>& files);

// The compiler flags the user chose that differ between the files, as "-DNDEBUG only in [2]"
// ("" when the flags are the same set).
std::string flags_difference(const std::vector<const ResultFile*>& files);

}  // namespace suite
