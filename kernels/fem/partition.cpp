#include "kernels/fem/partition.hpp"

#include <algorithm>
#include <mutex>
#include <numeric>
#include <stdexcept>
#include <utility>

#include "harness/common/units.hpp"

#if defined(SUITE_HAVE_SPARSE)
#include <metis.h>
#endif

namespace suite::fem {

const ChoiceTable<PartitionScheme>& partition_schemes() {
    static const ChoiceTable<PartitionScheme> table{
        "partition",
        {{"curve", "the ordering's rows in ranges balanced by nonzeros", PartitionScheme::curve},
         {"metis", "METIS k-way", PartitionScheme::metis}}};
    return table;
}

PartitionScheme parse_partition_scheme(const std::string& name) { return partition_schemes().at(name).what; }

const char* partition_scheme_name(PartitionScheme s) {
    for (const auto& c : partition_schemes().all())
        if (c.what == s) return c.name.c_str();
    return "?";
}

namespace {

void partition_check_parts(int parts) {
    if (parts < 1) throw std::invalid_argument("a partition into " + std::to_string(parts) + " parts");
}

// part_of from consecutive ranges of the rows as numbered (order the identity).
Partition partition_from_offsets(std::int64_t n, std::vector<std::int64_t> offsets) {
    Partition out;
    out.parts = static_cast<int>(offsets.size()) - 1;
    out.order.resize(static_cast<std::size_t>(n));
    std::iota(out.order.begin(), out.order.end(), 0u);
    out.part_of.resize(static_cast<std::size_t>(n));
    for (int q = 0; q < out.parts; ++q)
        for (std::int64_t i = offsets[static_cast<std::size_t>(q)]; i < offsets[static_cast<std::size_t>(q) + 1]; ++i)
            out.part_of[static_cast<std::size_t>(i)] = q;
    out.offsets = std::move(offsets);
    return out;
}

}  // namespace

Partition partition_from_parts(std::int64_t n, int parts, std::vector<std::int32_t> part_of) {
    partition_check_parts(parts);
    if (static_cast<std::int64_t>(part_of.size()) != n)
        throw std::invalid_argument("a part for each of " + std::to_string(n) + " rows, not " +
                                    std::to_string(part_of.size()));
    for (const std::int32_t q : part_of)
        if (q < 0 || q >= parts)
            throw std::invalid_argument("part " + std::to_string(q) + " of a partition into " + std::to_string(parts));
    Partition out;
    out.parts = parts;
    out.offsets.assign(static_cast<std::size_t>(parts) + 1, 0);
    for (const std::int32_t q : part_of) ++out.offsets[static_cast<std::size_t>(q) + 1];
    std::partial_sum(out.offsets.begin(), out.offsets.end(), out.offsets.begin());
    std::vector<std::int64_t> next(out.offsets.begin(), out.offsets.end() - 1);
    out.order.resize(static_cast<std::size_t>(n));
    for (std::size_t i = 0; i < part_of.size(); ++i) {
        std::int64_t& at = next[static_cast<std::size_t>(part_of[i])];
        out.order[static_cast<std::size_t>(at++)] = static_cast<std::uint32_t>(i);
    }
    out.part_of = std::move(part_of);
    return out;
}

Partition curve_partition(const Pattern& p, int parts) {
    partition_check_parts(parts);
    const std::uint64_t nz = p.nnz();
    std::vector<std::int64_t> offsets(static_cast<std::size_t>(parts) + 1, 0);
    offsets.back() = p.n;
    const std::uint32_t* const first = p.row_ptr;
    const std::uint32_t* const last = p.row_ptr + p.n + 1;
    for (int k = 1; k < parts; ++k) {
        // The row boundary nearest k/parts of the nonzeros; never before the previous one.
        const std::uint64_t target = nz * static_cast<std::uint64_t>(k) / static_cast<std::uint64_t>(parts);
        std::int64_t i = std::lower_bound(first, last, target) - first;
        if (i > 0 && target - first[i - 1] < first[i] - target) --i;
        offsets[static_cast<std::size_t>(k)] = std::clamp(i, offsets[static_cast<std::size_t>(k) - 1], p.n);
    }
    return partition_from_offsets(p.n, std::move(offsets));
}

void require_metis() {
#if !defined(SUITE_HAVE_SPARSE)
    throw UsageError(
        "--strategy=metis: this build has no METIS (Debian: libmetis-dev; install it and rebuild), or use "
        "--strategy=curve");
#endif
}

Partition metis_partition(const Pattern& p, int parts, std::uint64_t seed) {
    partition_check_parts(parts);
    require_metis();
#if !defined(SUITE_HAVE_SPARSE)
    (void)p, (void)seed;
    return {};
#else
    std::vector<std::int32_t> part_of(static_cast<std::size_t>(p.n), 0);
    // METIS is not asked for one part (there is nothing to cut); every rank then owns its rows in order.
    if (parts > 1 && p.n > 0) {
        std::vector<idx_t> xadj(static_cast<std::size_t>(p.n) + 1, 0), adj, weight(static_cast<std::size_t>(p.n));
        adj.reserve(p.nnz());
        for (std::int64_t i = 0; i < p.n; ++i) {
            for (std::uint32_t k = p.row_ptr[i]; k < p.row_ptr[i + 1]; ++k)
                if (p.col[k] != i) adj.push_back(static_cast<idx_t>(p.col[k]));
            xadj[static_cast<std::size_t>(i) + 1] = static_cast<idx_t>(adj.size());
            weight[static_cast<std::size_t>(i)] = static_cast<idx_t>(p.row_ptr[i + 1] - p.row_ptr[i]);
        }
        idx_t n = static_cast<idx_t>(p.n), constraints = 1, np = parts, cut = 0;
        idx_t options[METIS_NOPTIONS];
        METIS_SetDefaultOptions(options);
        options[METIS_OPTION_NUMBERING] = 0;
        options[METIS_OPTION_SEED] = static_cast<idx_t>(seed % 2147483647u);
        std::vector<idx_t> got(static_cast<std::size_t>(p.n));
        // METIS draws from GKlib's random generator, whose state is global: two threads partitioning
        // at once (ranks made of threads, in the tests) would each get a partition of neither seed.
        static std::mutex metis_lock;
        const std::lock_guard<std::mutex> hold(metis_lock);
        const int status = METIS_PartGraphKway(&n, &constraints, xadj.data(), adj.data(), weight.data(), nullptr,
                                               nullptr, &np, nullptr, nullptr, options, &cut, got.data());
        if (status != METIS_OK)
            throw std::runtime_error("METIS_PartGraphKway failed (status " + std::to_string(status) + ")");
        for (std::size_t i = 0; i < got.size(); ++i) part_of[i] = static_cast<std::int32_t>(got[i]);
    }
    return partition_from_parts(p.n, parts, std::move(part_of));
#endif
}

Partition make_partition(PartitionScheme s, const Pattern& p, int parts, std::uint64_t seed) {
    return s == PartitionScheme::curve ? curve_partition(p, parts) : metis_partition(p, parts, seed);
}

PartitionQuality partition_quality(const Pattern& p, const Partition& part) {
    const std::size_t np = static_cast<std::size_t>(part.parts);
    PartitionQuality q;
    q.rows.assign(np, 0);
    q.nnz.assign(np, 0);
    q.halo.assign(np, 0);
    q.neighbours.assign(np, 0);
    // Stamps: the last part that counted a column or a neighbour, so that each counts once a part.
    std::vector<std::int32_t> col_seen(static_cast<std::size_t>(p.n), -1), part_seen(np, -1);
    for (int r = 0; r < part.parts; ++r) {
        const std::size_t rs = static_cast<std::size_t>(r);
        for (std::int64_t at = part.offsets[rs]; at < part.offsets[rs + 1]; ++at) {
            const std::uint32_t i = part.order[static_cast<std::size_t>(at)];
            ++q.rows[rs];
            q.nnz[rs] += p.row_ptr[i + 1] - p.row_ptr[i];
            for (std::uint32_t k = p.row_ptr[i]; k < p.row_ptr[i + 1]; ++k) {
                const std::uint32_t c = p.col[k];
                const std::int32_t owner = part.part_of[c];
                if (owner == r) continue;
                if (i < c) ++q.edge_cut;  // each edge once, from its lower row: the pattern is symmetric
                if (col_seen[c] != r) col_seen[c] = r, ++q.halo[rs];
                if (part_seen[static_cast<std::size_t>(owner)] != r)
                    part_seen[static_cast<std::size_t>(owner)] = r, ++q.neighbours[rs];
            }
        }
    }
    auto imbalance = [&](const std::vector<std::int64_t>& v) {
        const double total = static_cast<double>(std::accumulate(v.begin(), v.end(), std::int64_t{0}));
        if (total <= 0) return 1.0;
        return static_cast<double>(*std::max_element(v.begin(), v.end())) / (total / static_cast<double>(np));
    };
    q.imbalance_rows = imbalance(q.rows);
    q.imbalance_nnz = imbalance(q.nnz);
    return q;
}

LocalMatrix local_matrix(const Pattern& p, const double* a, const double* m, const Partition& part, int rank) {
    if (rank < 0 || rank >= part.parts)
        throw std::invalid_argument("part " + std::to_string(rank) + " of a partition into " +
                                    std::to_string(part.parts));
    const std::size_t n = static_cast<std::size_t>(p.n);
    const std::int64_t lo = part.offsets[static_cast<std::size_t>(rank)],
                       hi = part.offsets[static_cast<std::size_t>(rank) + 1];
    LocalMatrix lm;
    lm.rank = rank;
    lm.parts = part.parts;
    lm.owned = hi - lo;
    std::vector<std::uint32_t> place(n);
    for (std::size_t at = 0; at < n; ++at) place[part.order[at]] = static_cast<std::uint32_t>(at);
    // The halo, as places of the partition's numbering: sorted, it is grouped by owner (parts own
    // consecutive places) and in the owner's own order inside a group.
    std::vector<std::uint32_t> halo;
    for (std::int64_t at = lo; at < hi; ++at) {
        const std::uint32_t i = part.order[static_cast<std::size_t>(at)];
        for (std::uint32_t k = p.row_ptr[i]; k < p.row_ptr[i + 1]; ++k)
            if (place[p.col[k]] < lo || place[p.col[k]] >= hi) halo.push_back(place[p.col[k]]);
    }
    std::sort(halo.begin(), halo.end());
    halo.erase(std::unique(halo.begin(), halo.end()), halo.end());
    lm.halo = static_cast<std::int64_t>(halo.size());
    std::vector<std::int64_t> local(n, -1);
    lm.global.reserve(static_cast<std::size_t>(lm.owned + lm.halo));
    for (std::int64_t at = lo; at < hi; ++at) {
        local[part.order[static_cast<std::size_t>(at)]] = at - lo;
        lm.global.push_back(part.order[static_cast<std::size_t>(at)]);
    }
    for (std::size_t h = 0; h < halo.size(); ++h) {
        local[part.order[halo[h]]] = lm.owned + static_cast<std::int64_t>(h);
        lm.global.push_back(part.order[halo[h]]);
    }
    for (std::int64_t at = lo; at < hi; ++at) {
        const std::uint32_t i = part.order[static_cast<std::size_t>(at)];
        for (std::uint32_t k = p.row_ptr[i]; k < p.row_ptr[i + 1]; ++k) {
            lm.col.push_back(static_cast<std::uint32_t>(local[p.col[k]]));
            if (a) lm.a.push_back(a[k]);
            if (m) lm.m.push_back(m[k]);
        }
        lm.row_ptr.push_back(static_cast<std::uint32_t>(lm.col.size()));
    }
    // What each other part reads of this one's rows, found from its rows (every rank has them
    // all), as this part's local indices in ascending order: the order of that part's halo.
    std::vector<std::vector<std::uint32_t>> send(static_cast<std::size_t>(part.parts));
    for (int q = 0; q < part.parts; ++q) {
        if (q == rank) continue;
        auto& s = send[static_cast<std::size_t>(q)];
        for (std::int64_t at = part.offsets[static_cast<std::size_t>(q)];
             at < part.offsets[static_cast<std::size_t>(q) + 1]; ++at) {
            const std::uint32_t i = part.order[static_cast<std::size_t>(at)];
            for (std::uint32_t k = p.row_ptr[i]; k < p.row_ptr[i + 1]; ++k)
                if (part.part_of[p.col[k]] == rank) s.push_back(static_cast<std::uint32_t>(local[p.col[k]]));
        }
        std::sort(s.begin(), s.end());
        s.erase(std::unique(s.begin(), s.end()), s.end());
    }
    std::vector<std::int64_t> recv_lo(static_cast<std::size_t>(part.parts), 0),
        recv_count(static_cast<std::size_t>(part.parts), 0);
    for (std::size_t h = halo.size(); h-- > 0;) {
        const std::size_t owner = static_cast<std::size_t>(part.part_of[part.order[halo[h]]]);
        recv_lo[owner] = static_cast<std::int64_t>(h);
        ++recv_count[owner];
    }
    for (int q = 0; q < part.parts; ++q) {
        const std::size_t qs = static_cast<std::size_t>(q);
        if (send[qs].empty() && recv_count[qs] == 0) continue;
        lm.links.push_back({q, std::move(send[qs]), recv_lo[qs], recv_count[qs]});
    }
    return lm;
}

}  // namespace suite::fem
