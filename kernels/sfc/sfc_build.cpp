// sfc-build: a mesh reordered along a space-filling curve (or by RCM). One repetition:
//   box   = bounding box of the vertices
//   for e:        key[e] = curve(quantize(centroid(e) in box, depth))            phase "keys"
//   perm  = elements stably sorted by key                                      phase "sort"
//   for i, j:     at v = conn[perm[i]][j]'s first touch: new_id[v] = next++;   phase "renumber"
//                 conn'[i][j] = new_id[v];  x'[new_id[v]] = x[v]
//
// Timing the phases apart. A Kernel never reads a clock, so each phase is its own measured
// point: the variant (--phase=keys|sort|renumber|all) makes run() do that phase alone, its
// inputs made, untimed, in setup(). The runner times a phase exactly as it times everything
// else, and keys + sort + renumber can be set against "all" from the same run. (Timing the
// phases inside one run() would need a clock in the kernel; a separate benchmark command would
// time them by other rules than the rest of the suite.)
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "harness/common/choice_table.hpp"
#include "harness/common/text.hpp"
#include "harness/common/units.hpp"
#include "harness/kernel/blocks.hpp"
#include "harness/kernel/kernel.hpp"
#include "kernels/mesh/mesh_spec.hpp"
#include "kernels/sfc/pipeline.hpp"
#include "kernels/sfc/sfc_checks.hpp"

namespace suite::sfc {

namespace {

// The phases --phase measures apart, in the order they run; the plain kernel "" (--phase=all)
// runs them all.
enum class Phase { keys, sort, renumber };

const ChoiceTable<Phase>& phases() {
    static const ChoiceTable<Phase> table{"phase",
                                          {{"keys", "the bounding box and every element's key", Phase::keys},
                                           {"sort", "the elements stably sorted by key", Phase::sort},
                                           {"renumber", "vertices renumbered, the mesh rewritten", Phase::renumber}}};
    return table;
}

// The phase a variant measures alone; none for the plain kernel.
std::optional<Phase> phase_of(const std::string& variant) {
    if (variant.empty()) return std::nullopt;
    return phases().at(variant).what;
}

constexpr std::uint32_t poison32 = std::numeric_limits<std::uint32_t>::max();

std::string mesh_of(const KernelConfig& cfg) { return cfg.mesh.empty() ? mesh::disk_spec_for(cfg.size) : cfg.mesh; }

class SfcBuild final : public Kernel {
public:
    explicit SfcBuild(const KernelConfig& cfg)
        : cfg_(cfg), method_(parse_method(cfg.access.name)), only_(phase_of(cfg.variant)) {}

    void setup(Arena& arena) override {
        spec_ = mesh_of(cfg_);
        mesh::Mesh m = mesh::load_mesh(mesh::parse_mesh_spec(spec_));
        dim_ = m.dim;
        k_ = m.corners();
        ne_ = m.elements();
        nv_ = m.vertices();
        const char* const names[3] = {"x", "y", "z"};
        double* in_xyz[3] = {};
        double* out_xyz[3] = {};
        for (int a = 0; a < dim_; ++a) {
            in_xyz[a] = arena.allocate<double>(names[a], nv_);
            out_xyz[a] = arena.allocate<double>(std::string("new-") + names[a], nv_);
        }
        conn_ = arena.allocate<std::uint32_t>("conn", ne_ * k_);
        arrays_.keys = arena.allocate<std::uint64_t>("keys", ne_);
        arrays_.perm = arena.allocate<std::uint32_t>("perm", ne_);
        arrays_.sort = {
            arena.allocate<std::uint64_t>("sort-keys-a", ne_), arena.allocate<std::uint64_t>("sort-keys-b", ne_),
            arena.allocate<std::uint32_t>("sort-index-a", ne_), arena.allocate<std::uint32_t>("sort-index-b", ne_)};
        arrays_.new_id = arena.allocate<std::uint32_t>("new-id", nv_);
        const std::size_t words = rank_words(ne_, k_);
        arrays_.renumber = {arena.allocate<std::uint32_t>("first-touch", nv_),
                            arena.allocate<std::uint64_t>("rank-bits", words),
                            arena.allocate<std::uint32_t>("rank-counts", words)};
        arrays_.out = {arena.allocate<std::uint32_t>("new-conn", ne_ * k_), out_xyz[0], out_xyz[1], out_xyz[2]};
        // First touch by the computing threads, each its block of elements and of vertices, the
        // blocks the phases use. Outputs start as poison, so a phase that never ran fails verify().
        const std::int64_t ne = static_cast<std::int64_t>(ne_), nv = static_cast<std::int64_t>(nv_);
        const double* src[3] = {m.x.data(), m.y.data(), dim_ == 3 ? m.z.data() : nullptr};
        const PipelineArrays a = arrays_;
        const int k = k_, dim = dim_;
        std::uint32_t* conn = conn_;
#pragma omp parallel
        {
            const Block eb = my_block(ne);
            for (std::int64_t e = eb.lo; e < eb.hi; ++e) {
                for (int j = 0; j < k; ++j) {
                    conn[e * k + j] = m.conn[e * k + j];
                    a.out.conn[e * k + j] = poison32;
                }
                a.keys[e] = ~0ULL;
                a.perm[e] = poison32;
                a.sort.keys_a[e] = a.sort.keys_b[e] = 0;
                a.sort.index_a[e] = a.sort.index_b[e] = 0;
            }
            const Block vb = my_block(nv);
            for (std::int64_t v = vb.lo; v < vb.hi; ++v) {
                for (int d = 0; d < dim; ++d) {
                    in_xyz[d][v] = src[d][v];
                    out_xyz[d][v] = std::numeric_limits<double>::quiet_NaN();
                }
                a.new_id[v] = poison32;
                a.renumber.first[v] = poison32;
            }
            const Block wb = my_block(static_cast<std::int64_t>(words));
            for (std::int64_t w = wb.lo; w < wb.hi; ++w) a.renumber.bits[w] = a.renumber.rank[w] = 0;
        }
        in_ = {dim_, nv_, ne_, in_xyz[0], in_xyz[1], in_xyz[2], conn_};
        pipeline_ = std::make_unique<Pipeline>(in_, method_, max_depth(dim_), Encoder::best, arrays_);
        // A phase measured alone starts from the outputs of the phases before it.
        if (only_ && *only_ > Phase::keys) pipeline_->keys();
        if (only_ && *only_ > Phase::sort) pipeline_->sort();
    }

    void run(int calls) override {
        for (int c = 0; c < calls; ++c) {
            if (does(Phase::keys)) pipeline_->keys();
            if (does(Phase::sort)) pipeline_->sort();
            if (does(Phase::renumber)) pipeline_->renumber();
        }
    }

    Verification verify() override {
        Checks checks(in_, method_, max_depth(dim_), arrays_, pipeline_->frame());
        Verification out{true,
                         "mesh " + spec_ + " (" + std::to_string(ne_) + " " + mesh::element_word(dim_, true) + ", " +
                             std::to_string(nv_) + " vertices), " + cfg_.access.name + ": ",
                         0};
        std::vector<std::string> done;
        auto add = [&](const CheckResult& r) {
            done.push_back(r.what);
            if (!r.passed && out.passed) {
                out.passed = false;
                done.push_back("FAILED: " + r.failure);
            }
        };
        if (does(Phase::keys)) add(checks.keys());
        if (does(Phase::sort)) add(checks.sort());
        if (does(Phase::renumber)) add(checks.renumber());
        for (std::size_t i = 0; i < done.size(); ++i) out.detail += (i ? "; " : "") + done[i];
        return out;
    }

    // Bytes by the STREAM convention: each array a phase must read or write, counted once
    // (the mesh's connectivity and coordinates read to make keys, keys read and the
    // permutation written by the sort, the mesh read and written again by the renumbering).
    // The hardware estimate adds what the implementation really moves: write-allocate on every
    // store, the sort's two passes over (key, index) pairs, and the renumbering's three passes
    // over the corners (gather, first-touch minimum, rewrite) and four over the vertices.
    Work work() const override {
        const double n = static_cast<double>(ne_), v = static_cast<double>(nv_), k = k_, d = dim_;
        const double keys_s = n * (4 * k + 8 * d * k + 8), keys_h = n * (4 * k + 8 * d * k + 16);
        const double sort_s = n * (8 + 4), sort_h = n * (8 + 8 + 2 * 12 + 12 + 2 * 12 + 2 * 4);
        const double ren_s = n * (4 + 4 * k + 4 * k) + v * (8 * d * 2 + 4);
        const double ren_h = n * (4 + 4 * k + 2 * 4 * k) + n * k * (4 + 4) + n * k * (4 + 4 + 2 * 4) +
                             v * (8 * d * 3 + 4 * 3 + 8 + 2 * 4);
        Work w;
        w.units = n;
        if (does(Phase::keys)) w.stream_bytes += keys_s, w.hardware_bytes += keys_h;
        if (does(Phase::sort)) w.stream_bytes += sort_s, w.hardware_bytes += sort_h;
        if (does(Phase::renumber)) w.stream_bytes += ren_s, w.hardware_bytes += ren_h;
        w.footprint_bytes = static_cast<std::uint64_t>(n * (4 * k * 2 + 8 + 4 + 8 * 2 + 4 * 2) +
                                                       12.0 * std::ceil(n * k / 64) + v * (8 * d * 2 + 4 * 2));
        return w;
    }

private:
    // Whether a repetition runs phase `p`: all of them, or the one --phase measures alone.
    bool does(Phase p) const { return !only_ || *only_ == p; }

    KernelConfig cfg_;
    Method method_;
    std::optional<Phase> only_;
    std::string spec_;
    int dim_ = 2, k_ = 3;
    std::size_t ne_ = 0, nv_ = 0;
    std::uint32_t* conn_ = nullptr;
    mesh::MeshView in_;
    PipelineArrays arrays_;
    std::unique_ptr<Pipeline> pipeline_;
};

// Bytes a point needs at its peak: the kernel's arrays, the mesh as built before it is copied
// into them, and for RCM the vertex graph (about 150 bytes a vertex with Boost's copy of it).
std::uint64_t peak_bytes(const mesh::MeshCounts& c, Method method) {
    const std::uint64_t k = static_cast<std::uint64_t>(c.dim) + 1;
    const std::uint64_t arrays =
        c.elements * (8 * k + 8 + 4 + 16 + 8) + c.elements * k * 12 / 64 + c.vertices * (16 * c.dim + 8);
    const std::uint64_t mesh = c.elements * 4 * k + c.vertices * 8 * c.dim;
    return arrays + 2 * mesh + (method == Method::rcm ? 150 * c.vertices : 0);
}

void validate(const KernelConfig& cfg) {
    const Method method = parse_method(cfg.access.name);
    const std::string spec = mesh_of(cfg);
    const mesh::MeshCounts c = mesh::mesh_counts(mesh::parse_mesh_spec(spec));
    const std::uint64_t need = peak_bytes(c, method), have = available_memory_bytes(MemoryPolicy{});
    if (need > have)
        throw UsageError("sfc-build on --mesh=" + spec + " (" + std::to_string(c.elements) + " elements) needs about " +
                         format_bytes(need) + ", more than the " + format_bytes(have) +
                         " of memory available; use a smaller mesh");
}

const bool registered = [] {
    KernelEntry e;
    e.info.name = "sfc-build";
    e.info.group = "sfc";
    e.info.formula = "curve keys, sort, renumber";
    e.info.unit = "element";
    e.info.axis = AccessAxis::ordering;
    e.info.accesses = sorting_orderings().names();
    e.info.variants = {""};
    for (const auto& p : phases().names()) e.info.variants.push_back(p);
    e.info.size_kind = SizeKind::count;
    e.info.metric = Metric::bandwidth;
    // For triangles (work() has the formulas): keys 12+48 read, 8 written; sort 8 read, 4 written;
    // renumber 16 read, 12 written, plus the vertices.
    e.info.read_bytes_per_unit = 84;
    e.info.write_bytes_per_unit = 24;
    e.info.notes = "reorders a mesh along a curve (or RCM); --phase=" + join(phases().names(), "|") +
                   "|all; sized by --mesh, or a disk of at least --size triangles";
    e.make = [](const KernelConfig& cfg) { return std::make_unique<SfcBuild>(cfg); };
    e.validate = validate;
    e.mesh_elements = [](const std::string& spec) { return mesh::mesh_counts(mesh::parse_mesh_spec(spec)).elements; };
    e.default_meshes = {"disk:refine=6", "disk:refine=10"};
    e.test_size = 1536;  // disk:refine=4
    return register_kernel(std::move(e));
}();

}  // namespace

}  // namespace suite::sfc
