#include "kernels/fem/assembly.hpp"

#include <omp.h>

#include <algorithm>
#include <atomic>

#include "harness/common/units.hpp"
#include "harness/kernel/blocks.hpp"
#include "kernels/fem/element.hpp"

namespace suite::fem {

namespace {

struct Corners {
    std::uint32_t v[3];
    double x[3], y[3];
};

inline Corners corners(const MeshArrays& m, std::int64_t e) {
    Corners c;
    for (int j = 0; j < 3; ++j) {
        c.v[j] = m.conn[3 * e + j];
        c.x[j] = m.x[c.v[j]];
        c.y[j] = m.y[c.v[j]];
    }
    return c;
}

// Adds row i of the element matrices (entries (i, 0..2) of A and M) into the global rows.
template <bool Atomic>
inline void add_row(const Matrices& out, const Corners& c, const ElementMatrices& em, int i) {
    for (int j = 0; j < 3; ++j) {
        const std::int64_t k = find_entry(out.pattern, c.v[i], c.v[j]);
        if constexpr (Atomic) {
            std::atomic_ref<double>(out.a[k]).fetch_add(em.a[3 * i + j], std::memory_order_relaxed);
            std::atomic_ref<double>(out.m[k]).fetch_add(em.m[3 * i + j], std::memory_order_relaxed);
        } else {
            out.a[k] += em.a[3 * i + j];
            out.m[k] += em.m[3 * i + j];
        }
    }
}

template <bool Atomic>
inline void add_element(const MeshArrays& m, const Matrices& out, double delta, std::int64_t e) {
    const Corners c = corners(m, e);
    ElementMatrices em;
    element_matrices(c.x, c.y, delta, em);
    for (int i = 0; i < 3; ++i) add_row<Atomic>(out, c, em, i);
}

void zero_rows(const Matrices& out) {
    const Block rb = my_block(out.pattern.n);
    const std::uint32_t lo = out.pattern.row_ptr[rb.lo], hi = out.pattern.row_ptr[rb.hi];
    std::fill(out.a + lo, out.a + hi, 0.0);
    std::fill(out.m + lo, out.m + hi, 0.0);
}

}  // namespace

const ChoiceTable<Strategy>& assembly_strategies() {
    static const ChoiceTable<Strategy> table{
        "assembly strategy",
        {{"serial", "one thread, elements in order", Strategy::serial},
         {"colour", "elements coloured so that no two of one colour share a vertex", Strategy::colour},
         {"partition", "one run of elements a thread, shared rows added apart", Strategy::partition},
         {"atomic", "every addition an atomic add", Strategy::atomic}}};
    return table;
}

Strategy parse_strategy(const std::string& name) { return assembly_strategies().at(name).what; }

const char* strategy_name(Strategy s) {
    for (const auto& c : assembly_strategies().all())
        if (c.what == s) return c.name.c_str();
    return "?";
}

StrategyPlan plan_strategy(const MeshArrays& m, Strategy s, int threads) {
    StrategyPlan p;
    p.strategy = s;
    p.threads = threads;
    const std::int64_t ne = m.ne, nv = m.nv;
    if (s == Strategy::atomic) p.synchronised = 3 * static_cast<std::uint64_t>(ne);
    if (s == Strategy::colour) {
        // Greedy first fit in mesh order: an element takes the smallest colour none of the
        // elements at its corners has. A vertex keeps a bit mask of the colours used at it
        // (a vertex of a triangle mesh with more than 64 triangles at it falls back to a scan).
        std::vector<std::uint32_t> colour(static_cast<std::size_t>(ne));
        std::vector<std::uint64_t> used(static_cast<std::size_t>(nv), 0);
        std::vector<std::vector<std::uint32_t>> members;
        for (std::int64_t e = 0; e < ne; ++e) {
            const std::uint32_t* c = m.conn + 3 * e;
            const std::uint64_t taken = used[c[0]] | used[c[1]] | used[c[2]];
            if (~taken == 0)
                throw UsageError(
                    "the colouring of this mesh needs more than 64 colours (a vertex with more than 64 triangles)");
            const int k = __builtin_ctzll(~taken);
            colour[static_cast<std::size_t>(e)] = static_cast<std::uint32_t>(k);
            for (int j = 0; j < 3; ++j) used[c[j]] |= 1ULL << k;
            if (static_cast<std::size_t>(k) >= members.size()) members.resize(static_cast<std::size_t>(k) + 1);
            members[static_cast<std::size_t>(k)].push_back(static_cast<std::uint32_t>(e));
        }
        p.colours = static_cast<int>(members.size());
        p.colour_ptr.push_back(0);
        for (const auto& list : members) {
            p.colour_elements.insert(p.colour_elements.end(), list.begin(), list.end());
            p.colour_ptr.push_back(static_cast<std::uint32_t>(p.colour_elements.size()));
        }
    }
    if (s == Strategy::partition) {
        // The first and last thread whose block has an element at each vertex.
        std::vector<int> first(static_cast<std::size_t>(nv), threads), last(static_cast<std::size_t>(nv), -1);
        for (int t = 0; t < threads; ++t) {
            const Block b = static_block(ne, t, threads);
            for (std::int64_t e = b.lo; e < b.hi; ++e)
                for (int j = 0; j < 3; ++j) {
                    const std::uint32_t v = m.conn[3 * e + j];
                    first[v] = std::min(first[v], t);
                    last[v] = std::max(last[v], t);
                }
        }
        p.shared.assign(static_cast<std::size_t>(nv), 0);
        for (std::int64_t v = 0; v < nv; ++v)
            if (first[static_cast<std::size_t>(v)] != last[static_cast<std::size_t>(v)]) {
                p.shared[static_cast<std::size_t>(v)] = 1;
                ++p.shared_vertices;
            }
        // The owner of a shared vertex is the first thread at it; it takes every contribution to it.
        std::vector<std::vector<std::uint32_t>> items(static_cast<std::size_t>(threads));
        for (std::int64_t e = 0; e < ne; ++e)
            for (int j = 0; j < 3; ++j) {
                const std::uint32_t v = m.conn[3 * e + j];
                if (p.shared[v])
                    items[static_cast<std::size_t>(first[v])].push_back(static_cast<std::uint32_t>(e) << 2 |
                                                                        static_cast<std::uint32_t>(j));
            }
        p.owned_ptr.push_back(0);
        for (const auto& list : items) {
            p.owned_items.insert(p.owned_items.end(), list.begin(), list.end());
            p.owned_ptr.push_back(static_cast<std::uint32_t>(p.owned_items.size()));
        }
        p.synchronised = p.owned_items.size();
    }
    return p;
}

void assemble(const MeshArrays& m, const Matrices& out, double delta, const StrategyPlan& plan) {
    const Strategy s = plan.strategy;
#pragma omp parallel
    {
        zero_rows(out);
#pragma omp barrier
        if (s == Strategy::serial) {
#pragma omp single nowait
            for (std::int64_t e = 0; e < m.ne; ++e) add_element<false>(m, out, delta, e);
        } else if (s == Strategy::atomic) {
            const Block b = my_block(m.ne);
            for (std::int64_t e = b.lo; e < b.hi; ++e) add_element<true>(m, out, delta, e);
        } else if (s == Strategy::colour) {
            for (int c = 0; c < plan.colours; ++c) {
                const std::int64_t lo = plan.colour_ptr[static_cast<std::size_t>(c)],
                                   hi = plan.colour_ptr[static_cast<std::size_t>(c) + 1];
                const Block b = my_block(hi - lo);
                for (std::int64_t i = lo + b.lo; i < lo + b.hi; ++i)
                    add_element<false>(m, out, delta, plan.colour_elements[static_cast<std::size_t>(i)]);
#pragma omp barrier
            }
        } else {
            // Rows of vertices inside the block directly; then the shared vertices this thread owns.
            // The two write disjoint rows of every other thread, so no barrier is needed between them.
            const std::uint8_t* shared = plan.shared.data();
            const Block b = my_block(m.ne);
            for (std::int64_t e = b.lo; e < b.hi; ++e) {
                const Corners c = corners(m, e);
                ElementMatrices em;
                element_matrices(c.x, c.y, delta, em);
                for (int i = 0; i < 3; ++i)
                    if (!shared[c.v[i]]) add_row<false>(out, c, em, i);
            }
            const int t = omp_get_thread_num();
            for (std::uint32_t k = plan.owned_ptr[static_cast<std::size_t>(t)];
                 k < plan.owned_ptr[static_cast<std::size_t>(t) + 1]; ++k) {
                const std::uint32_t item = plan.owned_items[k];
                const Corners c = corners(m, item >> 2);
                ElementMatrices em;
                element_matrices(c.x, c.y, delta, em);
                add_row<false>(out, c, em, static_cast<int>(item & 3));
            }
        }
    }
}

AssembledCsr assemble_reference(const MeshArrays& m, double delta) {
    AssembledCsr r;
    r.row_ptr.resize(static_cast<std::size_t>(m.nv) + 1);
    std::vector<std::uint32_t> v2e_ptr(static_cast<std::size_t>(m.nv) + 1), v2e(3 * static_cast<std::size_t>(m.ne)),
        fill(static_cast<std::size_t>(m.nv));
    std::vector<std::uint64_t> partial(2);
    Pattern p{m.nv, r.row_ptr.data(), nullptr};
    const PatternScratch scratch{v2e_ptr.data(), v2e.data(), fill.data(), partial.data()};
    const int saved = omp_get_max_threads();
    omp_set_num_threads(1);
    build_pattern(m, p, scratch);
    r.col.resize(p.nnz());
    p.col = r.col.data();
    build_pattern(m, p, scratch);
    r.a.assign(r.col.size(), 0.0);
    r.m.assign(r.col.size(), 0.0);
    const Matrices out{p, r.a.data(), r.m.data()};
    for (std::int64_t e = 0; e < m.ne; ++e) add_element<false>(m, out, delta, e);
    omp_set_num_threads(saved);
    return r;
}

}  // namespace suite::fem
