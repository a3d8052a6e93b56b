#pragma once
// Assembly of A and M into a CSR pattern built beforehand, by four strategies that differ only in
// how the threads add element matrices into the shared rows:
//   serial     one thread, the element loop in mesh order;
//   colour     elements grouped by a greedy colouring (no two elements of a colour share a vertex),
//              one colour after another, a barrier between colours: no update is synchronised,
//              but consecutive elements of a colour lie far apart on the mesh;
//   partition  each thread its contiguous block of elements (along the curve when the mesh is
//              ordered by one); rows of vertices inside a block are added directly, rows of the
//              vertices shared between blocks are handled separately: each shared vertex has one
//              owner thread, which computes the contributions of every element at that vertex;
//   atomic     each thread its block of elements, every addition an atomic add.
// Every strategy computes the same element matrices (element.hpp); only the summation order of
// an entry differs, so they agree with the serial matrix to round-off.
#include <cstdint>
#include <string>
#include <vector>

#include "harness/common/choice_table.hpp"
#include "kernels/fem/csr.hpp"

namespace suite::fem {

enum class Strategy { serial, colour, partition, atomic };

// --strategy's choices for the assembly, one table (choice_table.hpp): names, help lines, behaviour.
const ChoiceTable<Strategy>& assembly_strategies();
// The table's entry; throws UsageError for another name.
Strategy parse_strategy(const std::string& name);
const char* strategy_name(Strategy s);

// The global matrices: A and M share the pattern.
struct Matrices {
    Pattern pattern;
    double* a = nullptr;
    double* m = nullptr;
};

// What a strategy needs beyond the mesh, made once before the timed loop, for a team of
// `threads`. Vectors: this is setup data of a few bytes an element, not measured.
struct StrategyPlan {
    Strategy strategy = Strategy::serial;
    int threads = 1;
    // colour: elements grouped by colour, in mesh order within a colour.
    std::vector<std::uint32_t> colour_ptr, colour_elements;
    // partition: 1 for a vertex whose elements lie in more than one thread's block; per thread,
    // the (element << 2 | corner) contributions to the shared vertices it owns.
    std::vector<std::uint8_t> shared;
    std::vector<std::uint32_t> owned_ptr, owned_items;
    // Element contributions (one element's row: three entries of A and three of M) that needed
    // synchronisation: atomic ones, or ones routed to a shared vertex's owner.
    std::uint64_t synchronised = 0;
    std::uint64_t shared_vertices = 0;
    int colours = 0;
};

StrategyPlan plan_strategy(const MeshArrays& mesh, Strategy s, int threads);

// Zeroes the values and assembles, with the current OpenMP team (of plan.threads threads). The
// values are zeroed by row blocks, the split of their first touch.
void assemble(const MeshArrays& mesh, const Matrices& out, double delta, const StrategyPlan& plan);

// The matrices of one mesh, assembled serially into vectors: the reference of verify() and tests.
struct AssembledCsr {
    std::vector<std::uint32_t> row_ptr, col;
    std::vector<double> a, m;
    Pattern pattern() { return {static_cast<std::int64_t>(row_ptr.size()) - 1, row_ptr.data(), col.data()}; }
};
AssembledCsr assemble_reference(const MeshArrays& mesh, double delta);

}  // namespace suite::fem
