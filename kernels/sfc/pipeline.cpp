#include "kernels/sfc/pipeline.hpp"

#include <algorithm>
#include <numeric>

#include "harness/kernel/blocks.hpp"
#include "harness/kernel/permutation.hpp"
#include "kernels/sfc/rcm.hpp"

namespace suite::sfc {

Pipeline::Pipeline(const mesh::MeshView& in, Method method, int depth, Encoder encoder, const PipelineArrays& arrays)
    : in_(in), method_(method), depth_(depth), encoder_(encoder), a_(arrays) {}

void Pipeline::keys() {
    if (method_ == Method::rcm) {
        rcm_vertex_order(in_, a_.new_id);
        const int k = in_.dim + 1;
        const std::int64_t ne = static_cast<std::int64_t>(in_.elements);
#pragma omp parallel
        {
            const Block b = my_block(ne);
            for (std::int64_t e = b.lo; e < b.hi; ++e) {
                const std::uint32_t* c = in_.conn + e * k;
                std::uint32_t low = a_.new_id[c[0]];
                for (int j = 1; j < k; ++j) low = std::min(low, a_.new_id[c[j]]);
                a_.keys[e] = low;
            }
        }
        return;
    }
    frame_ = key_frame(in_, depth_);
    const Curve c = method_ == Method::morton    ? Curve::morton
                    : method_ == Method::hilbert ? Curve::hilbert
                                                 : Curve::morton_recursive;
    compute_keys(in_, frame_, c, a_.keys, encoder_);
}

void Pipeline::sort() { sort_by_key(a_.keys, in_.elements, key_bits(), a_.perm, a_.sort); }

void Pipeline::renumber() {
    if (method_ == Method::rcm)
        apply_vertex_order(in_, a_.perm, a_.new_id, a_.out);
    else
        renumber_first_touch(in_, a_.perm, a_.new_id, a_.renumber, a_.out);
}

Reordered reorder(const mesh::Mesh& m, Method method, int depth, Encoder encoder) {
    const std::size_t ne = m.elements(), nv = m.vertices();
    Reordered r;
    r.mesh.dim = m.dim;
    r.mesh.conn.resize(m.conn.size());
    r.mesh.x.resize(nv);
    r.mesh.y.resize(nv);
    if (m.dim == 3) r.mesh.z.resize(nv);
    r.perm.resize(ne);
    r.new_id.resize(nv);
    std::vector<std::uint64_t> keys(ne), ka(ne), kb(ne);
    std::vector<std::uint32_t> ia(ne), ib(ne), first(nv), rank(rank_words(ne, m.corners()));
    std::vector<std::uint64_t> bits(rank.size());
    PipelineArrays a{keys.data(),
                     r.perm.data(),
                     {ka.data(), kb.data(), ia.data(), ib.data()},
                     r.new_id.data(),
                     {first.data(), bits.data(), rank.data()},
                     {r.mesh.conn.data(), r.mesh.x.data(), r.mesh.y.data(), m.dim == 3 ? r.mesh.z.data() : nullptr}};
    Pipeline p(m.view(), method, depth, encoder, a);
    p.keys();
    p.sort();
    p.renumber();
    return r;
}

mesh::Mesh permuted(const mesh::Mesh& m, const std::vector<std::uint32_t>& perm,
                    const std::vector<std::uint32_t>& new_id) {
    mesh::Mesh r;
    r.dim = m.dim;
    r.conn.resize(m.conn.size());
    r.x.resize(m.vertices());
    r.y.resize(m.vertices());
    if (m.dim == 3) r.z.resize(m.vertices());
    apply_vertex_order(m.view(), perm.data(), new_id.data(),
                       {r.conn.data(), r.x.data(), r.y.data(), m.dim == 3 ? r.z.data() : nullptr});
    return r;
}

Reordered shuffled(const mesh::Mesh& m, std::uint64_t seed) {
    Reordered r;
    r.perm.resize(m.elements());
    r.new_id.resize(m.vertices());
    shuffled_permutation(r.perm.data(), r.perm.size(), seed);
    // A different stream of the same seed for the vertices, so the two shuffles are unrelated.
    shuffled_permutation(r.new_id.data(), r.new_id.size(), seed ^ 0x9e3779b97f4a7c15ULL);
    r.mesh = permuted(m, r.perm, r.new_id);
    return r;
}

mesh::Mesh ordered(const mesh::Mesh& m, const std::string& ordering, std::uint64_t seed, int depth) {
    const Ordering& o = mesh_orderings().at(ordering).what;
    switch (o.how) {
        case Ordering::How::as_given:
            return m;
        case Ordering::How::shuffled:
            return shuffled(m, seed).mesh;
        case Ordering::How::sorted:
            break;
    }
    return reorder(m, o.method, depth).mesh;
}

}  // namespace suite::sfc
