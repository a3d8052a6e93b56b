#pragma once
// The rows of a finite element matrix shared out over P ranks, and one rank's share as it works
// on it. Pure set-up code: no communication. Every rank holds the whole pattern (the set-up is
// replicated) and computes the same partition, so each can also compute what the others own,
// need and send without asking them.
//   curve  P contiguous row ranges balanced by nonzeros: with the rows in a space-filling-curve
//          ordering (--ordering=hilbert, morton) each range is a piece of the curve, the thesis's
//          curve as a domain decomposition;
//   metis  METIS_PartGraphKway on the matrix graph, its parts made contiguous by a permutation of
//          the rows (parts in order, rows in their order inside a part), so that both partitions
//          are ranges of one row numbering and the distributed code is the same for both.
#include <cstdint>
#include <string>
#include <vector>

#include "harness/common/choice_table.hpp"
#include "kernels/fem/csr.hpp"

namespace suite::fem {

enum class PartitionScheme { curve, metis };

// fem-dist's --strategy choices, one table (choice_table.hpp); parse throws UsageError for another name.
const ChoiceTable<PartitionScheme>& partition_schemes();
PartitionScheme parse_partition_scheme(const std::string& name);
const char* partition_scheme_name(PartitionScheme s);

// Which rows each part owns. The parts own consecutive ranges of a renumbering of the rows.
struct Partition {
    int parts = 1;
    std::vector<std::uint32_t> order;   // order[new] = old: the global row that takes place `new`
    std::vector<std::int64_t> offsets;  // parts + 1: part q owns new places [offsets[q], offsets[q+1])
    std::vector<std::int32_t> part_of;  // per global row: its part
    std::int64_t rows_of(int q) const {
        return offsets[static_cast<std::size_t>(q) + 1] - offsets[static_cast<std::size_t>(q)];
    }
};

// The rows renumbered part after part, each part's rows in their order (part_of: per row, in
// [0, parts)): any assignment of rows to parts as ranges of one numbering.
Partition partition_from_parts(std::int64_t n, int parts, std::vector<std::int32_t> part_of);

// Contiguous ranges of the rows as numbered, each holding about nnz / parts nonzeros (a range
// ends at the row boundary nearest its share). Parts may be empty when parts > rows.
Partition curve_partition(const Pattern& p, int parts);

// METIS's k-way partition of the graph of p without its diagonal, each vertex weighted by its
// row's nonzeros (the work of the SpMV, as the curve's ranges balance it), with METIS's seed
// `seed` so that every rank computes the same parts. Throws UsageError naming libmetis-dev in a
// build without METIS.
Partition metis_partition(const Pattern& p, int parts, std::uint64_t seed);
// Throws that UsageError in a build without METIS; nothing otherwise.
void require_metis();

Partition make_partition(PartitionScheme s, const Pattern& p, int parts, std::uint64_t seed);

// What a partition costs the distributed product. The pattern must be symmetric (P1 patterns are).
struct PartitionQuality {
    std::int64_t edge_cut = 0;             // graph edges (off-diagonal pairs) whose ends lie in two parts
    std::vector<std::int64_t> rows, nnz;   // per part
    std::vector<std::int64_t> halo;        // per part: distinct columns it reads but does not own
    std::vector<std::int64_t> neighbours;  // per part: the parts that own those columns
    double imbalance_rows = 1;             // max rows / mean rows
    double imbalance_nnz = 1;              // max nnz / mean nnz
};
PartitionQuality partition_quality(const Pattern& p, const Partition& part);

// One neighbour of a part: the owned rows it reads (in the neighbour's order of them, which is
// this part's local order) and where its rows land in this part's halo.
struct HaloLink {
    int rank = -1;
    std::vector<std::uint32_t> send;  // local indices of owned rows whose values `rank` needs
    std::int64_t recv_offset = 0;     // its values go to local columns owned + recv_offset ...
    std::int64_t recv_count = 0;
};

// One part's rows, numbered locally: its owned rows 0 .. owned-1 (in the partition's order),
// then its halo columns owned .. owned+halo-1, grouped by owner rank ascending and in the owner's
// order inside a group (so that a neighbour's values arrive as one contiguous block). Each row
// keeps its entries in the global column order, so that y_i = Σ a_ik x_k is summed in the same
// order as the serial SpMV of the global matrix and comes out equal to the last bit.
struct LocalMatrix {
    int rank = 0, parts = 1;
    std::int64_t owned = 0, halo = 0;
    std::vector<std::uint32_t> row_ptr{0}, col;
    std::vector<double> a, m;           // empty when the caller gave no values
    std::vector<std::uint32_t> global;  // owned + halo: the global row of each local index
    std::vector<HaloLink> links;        // ascending rank; a link may only send or only receive
    Pattern pattern() { return {owned, row_ptr.data(), col.data()}; }
    std::uint64_t nnz() const { return row_ptr.back(); }
};

// Part `rank`'s local matrix; a and m (global values, in p's entry order) may be null.
LocalMatrix local_matrix(const Pattern& p, const double* a, const double* m, const Partition& part, int rank);

}  // namespace suite::fem
