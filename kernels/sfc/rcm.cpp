#include "kernels/sfc/rcm.hpp"

#include <boost/graph/compressed_sparse_row_graph.hpp>
#include <boost/graph/cuthill_mckee_ordering.hpp>

#include <iterator>
#include <vector>

#include "kernels/mesh/edges.hpp"

namespace suite::sfc {

namespace {

using Graph = boost::compressed_sparse_row_graph<boost::directedS, boost::no_property, boost::no_property,
                                                 boost::no_property, std::uint32_t, std::uint64_t>;

// The symmetric adjacency as (source, target) pairs sorted by source, generated on the fly so
// that Boost builds its graph without a second copy of every edge.
class PairIterator {
public:
    using iterator_category = std::input_iterator_tag;
    using value_type = std::pair<std::uint32_t, std::uint32_t>;
    using difference_type = std::ptrdiff_t;
    using pointer = const value_type*;
    using reference = const value_type&;

    PairIterator(const std::vector<std::uint64_t>& row, const std::vector<std::uint32_t>& target, std::uint64_t at)
        : row_(&row), target_(&target), at_(at) {
        settle();
    }
    reference operator*() const { return pair_; }
    pointer operator->() const { return &pair_; }
    PairIterator& operator++() {
        ++at_;
        settle();
        return *this;
    }
    PairIterator operator++(int) {
        PairIterator old = *this;
        ++*this;
        return old;
    }
    bool operator==(const PairIterator& o) const { return at_ == o.at_; }
    bool operator!=(const PairIterator& o) const { return at_ != o.at_; }

private:
    void settle() {
        if (at_ >= target_->size()) return;
        while ((*row_)[source_ + 1] <= at_) ++source_;
        pair_ = {source_, (*target_)[at_]};
    }
    const std::vector<std::uint64_t>* row_;
    const std::vector<std::uint32_t>* target_;
    std::uint64_t at_;
    std::uint32_t source_ = 0;
    value_type pair_{};
};

}  // namespace

void rcm_vertex_order(const mesh::MeshView& m, std::uint32_t* new_id) {
    const std::size_t nv = m.vertices;
    std::vector<std::uint64_t> row(nv + 1, 0);
    std::vector<std::uint32_t> target;
    {
        const mesh::EdgeTable edges = mesh::build_edges(m);
        for (std::size_t a = 0; a < nv; ++a)
            for (std::uint64_t k = edges.row[a]; k < edges.row[a + 1]; ++k) {
                ++row[a + 1];
                ++row[edges.upper[k] + 1];
            }
        for (std::size_t v = 0; v < nv; ++v) row[v + 1] += row[v];
        target.resize(row[nv]);
        std::vector<std::uint64_t> cursor(row.begin(), row.end() - 1);
        // Ascending a, and within a ascending b: every row comes out sorted.
        for (std::size_t a = 0; a < nv; ++a)
            for (std::uint64_t k = edges.row[a]; k < edges.row[a + 1]; ++k) {
                const std::uint32_t b = edges.upper[k];
                target[cursor[b]++] = static_cast<std::uint32_t>(a);
            }
        for (std::size_t a = 0; a < nv; ++a)
            for (std::uint64_t k = edges.row[a]; k < edges.row[a + 1]; ++k) target[cursor[a]++] = edges.upper[k];
    }
    const Graph g(boost::edges_are_sorted, PairIterator(row, target, 0), PairIterator(row, target, target.size()),
                  static_cast<Graph::vertices_size_type>(nv), static_cast<Graph::edges_size_type>(target.size()));
    std::vector<std::uint32_t>().swap(target);
    std::vector<std::uint32_t> order(nv);
    boost::cuthill_mckee_ordering(g, order.rbegin());  // written back to front: the reverse order
    for (std::size_t i = 0; i < nv; ++i) new_id[order[i]] = static_cast<std::uint32_t>(i);
}

}  // namespace suite::sfc
