// fem-assembly: the P1 Helmholtz matrices A and M added into a CSR pattern built beforehand.
// One repetition:
//   A = M = 0
//   for e:   A_e, M_e = element_matrices(corners of e)        (element.hpp: 175 flops, 3 exp)
//            for i, j: A[row v_i, col v_j] += A_e(i, j);  M[...] += M_e(i, j)
// --strategy says how the threads share the additions (assembly.hpp): serial, colour, partition,
// atomic. The record's facts say how many element rows needed synchronisation under the point's
// ordering and strategy, and, for the partition, how many vertices its blocks share.
#include <algorithm>
#include <limits>
#include <memory>
#include <string>

#include "harness/common/text.hpp"
#include "harness/common/units.hpp"
#include "harness/kernel/kernel.hpp"
#include "kernels/fem/element.hpp"
#include "kernels/fem/fem_checks.hpp"
#include "kernels/fem/fem_point.hpp"

namespace suite::fem {

namespace {

class FemAssembly final : public Kernel {
public:
    explicit FemAssembly(const KernelConfig& cfg) : cfg_(cfg), strategy_(parse_strategy(cfg.variant)) {}

    void setup(Arena& arena) override {
        d_.setup(arena, cfg_, FemPoint::Build::matrices);
        plan_ = plan_strategy(d_.mesh, strategy_, cfg_.threads);
        // Poisoned, so that verify() sees what run() assembled, not setup's serial matrices.
        std::fill(d_.matrices.a, d_.matrices.a + d_.nnz(), std::numeric_limits<double>::quiet_NaN());
    }

    void run(int calls) override {
        for (int c = 0; c < calls; ++c) assemble(d_.mesh, d_.matrices, d_.delta, plan_);
    }

    Verification verify() override {
        AssembledCsr ref = assemble_reference(d_.mesh, d_.delta);
        std::string failed = check_against(d_.matrices, ref, 1e-12);
        if (failed.empty()) failed = check_properties(d_.mesh, d_.matrices, d_.delta, 1e-12);
        Verification v;
        v.passed = failed.empty();
        v.detail = d_.describe(cfg_) + std::string(strategy_name(strategy_)) + ": " +
                   (failed.empty() ? "A and M equal the serial assembly entry by entry (1e-12 of the row), symmetric, "
                                     "ΣM = area, A 1 = -∫k²φ"
                                   : "FAILED: " + failed);
        return v;
    }

    std::vector<Fact> facts() const override {
        std::vector<Fact> f{{"synchronised", static_cast<double>(plan_.synchronised), "element rows"}};
        if (strategy_ == Strategy::colour) f.push_back({"colours", static_cast<double>(plan_.colours), "barriers"});
        if (strategy_ == Strategy::partition)
            f.push_back({"shared-vertices", static_cast<double>(plan_.shared_vertices), "vertices"});
        return f;
    }

    // STREAM convention: the connectivity, the coordinates, the row pointers and columns read
    // once, and the values of A and M zeroed then updated (read and written). The hardware
    // estimate adds the write-allocate of the zeroing and, per element row, its row's columns
    // searched (one 64 B line) and the corners' coordinates gathered (3 x 16 B).
    Work work() const override {
        const double ne = static_cast<double>(d_.mesh.ne), nv = static_cast<double>(d_.mesh.nv),
                     nz = static_cast<double>(d_.nnz());
        Work w;
        w.units = ne;
        w.flops = element_flops * ne + 18 * ne;  // and 18 additions into A and M
        w.stream_bytes = 12 * ne + 16 * nv + 4 * (nv + 1) + 4 * nz + 2 * (8 + 8 + 8) * nz;
        w.hardware_bytes = w.stream_bytes + 16 * nz + 3 * ne * (64 + 48);
        w.footprint_bytes = static_cast<std::uint64_t>(16 * nv + 12 * ne + 4 * (nv + 1) + 20 * nz);
        return w;
    }

private:
    KernelConfig cfg_;
    Strategy strategy_;
    FemPoint d_;
    StrategyPlan plan_;
};

const bool registered = [] {
    KernelEntry e;
    e.info.name = "fem-assembly";
    e.info.group = "fem";
    e.info.formula = "A[v_i, v_j] += A_e(i, j), M likewise";
    e.info.unit = "triangle";
    e.info.variants = assembly_strategies().names();
    e.info.variant_option = "strategy";
    e.info.default_variants = e.info.variants;
    e.info.single_thread_variants = {strategy_name(Strategy::serial)};
    e.info.params = {delta_param()};
    e.info.read_bytes_per_unit = 12 + 8 + 2 + 14 + 56;  // per triangle: corners, coordinates, rows, columns, values
    e.info.write_bytes_per_unit = 56;
    e.info.flops_per_unit = element_flops + 18;
    e.info.notes = "P1 Helmholtz assembly of A and M; --strategy=" + join(assembly_strategies().names(), ",") +
                   " (default all; serial on one thread)";
    set_mesh_sizing(e);
    e.make = [](const KernelConfig& cfg) { return std::make_unique<FemAssembly>(cfg); };
    e.validate = [](const KernelConfig& cfg) {
        if (parse_strategy(cfg.variant) == Strategy::serial && cfg.threads > 1)
            throw UsageError("fem-assembly's serial strategy runs on one thread, not " + std::to_string(cfg.threads) +
                             "; the parallel ones: colour, partition, atomic");
        validate_fem(cfg, "fem-assembly", true);
    };
    return register_kernel(std::move(e));
}();

}  // namespace

}  // namespace suite::fem
