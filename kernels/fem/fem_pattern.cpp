// fem-pattern: the CSR sparsity pattern of the P1 matrices, built from the mesh. One repetition:
//   for e, j:   v2e[v = conn[e][j]] += e                     (vertex-to-triangle lists)
//   for v:      row v = sorted distinct corners of v2e[v]    (counted, scanned, then filled)
// Built once before every other finite element kernel, and timed here on its own.
#include <algorithm>
#include <memory>
#include <string>

#include "harness/common/units.hpp"
#include "harness/kernel/kernel.hpp"
#include "kernels/fem/fem_checks.hpp"
#include "kernels/fem/fem_point.hpp"

namespace suite::fem {

namespace {

class FemPattern final : public Kernel {
public:
    explicit FemPattern(const KernelConfig& cfg) : cfg_(cfg) {}

    // The columns are poisoned after setup built them, so that verify() sees what run() built.
    void setup(Arena& arena) override {
        d_.setup(arena, cfg_, FemPoint::Build::pattern);
        std::fill(d_.pattern.col, d_.pattern.col + d_.nnz(), 0xffffffffu);
    }

    void run(int calls) override {
        for (int c = 0; c < calls; ++c) build_pattern(d_.mesh, d_.pattern, d_.scratch);
    }

    Verification verify() override {
        const std::string failed = check_pattern(d_.mesh, d_.pattern);
        Verification v;
        v.passed = failed.empty();
        v.detail =
            d_.describe(cfg_) +
            (failed.empty() ? "rows ascending, symmetric, every triangle's pairs present, vertices + 2 x edges entries"
                            : "FAILED: " + failed);
        return v;
    }

    // STREAM convention: the connectivity read, row pointers and columns written. The hardware
    // estimate adds the lists: counts (4 B a corner, scattered: a line each), the lists written
    // and read twice (count and fill), the corners gathered twice through them, and the columns'
    // write-allocate.
    Work work() const override {
        const double ne = static_cast<double>(d_.mesh.ne), nv = static_cast<double>(d_.mesh.nv),
                     nz = static_cast<double>(d_.nnz());
        Work w;
        w.units = ne;
        w.stream_bytes = 12 * ne + 4 * (nv + 1) + 4 * nz;
        w.hardware_bytes = 2 * 12 * ne + 2 * 3 * ne * 64 + 12 * ne * 3 + 2 * 9 * ne * 4 + 4 * nv * 6 + 8 * nz;
        w.footprint_bytes = static_cast<std::uint64_t>(16 * nv + 24 * ne + 12 * nv + 4 * nz);
        return w;
    }

private:
    KernelConfig cfg_;
    FemPoint d_;
};

const bool registered = [] {
    KernelEntry e;
    e.info.name = "fem-pattern";
    e.info.group = "fem";
    e.info.formula = "rows = corners of the triangles at each vertex";
    e.info.unit = "triangle";
    e.info.read_bytes_per_unit = 12;
    e.info.write_bytes_per_unit = 14;  // about 3.5 nonzeros a triangle, and half a row pointer
    e.info.notes = "the CSR pattern of the P1 matrices, from the mesh (built once before assembly, timed here apart)";
    set_mesh_sizing(e);
    e.make = [](const KernelConfig& cfg) { return std::make_unique<FemPattern>(cfg); };
    e.validate = [](const KernelConfig& cfg) { validate_fem(cfg, "fem-pattern", false); };
    return register_kernel(std::move(e));
}();

}  // namespace

}  // namespace suite::fem
