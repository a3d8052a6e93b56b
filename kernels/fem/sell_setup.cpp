// SELL-C-σ in the solver kernels: the parameter, the arena arrays, the facts (sell_setup.hpp).
#include "kernels/fem/sell_setup.hpp"

#include <cmath>
#include <stdexcept>

#include "harness/common/units.hpp"
#include "harness/common/usage_error.hpp"

namespace suite::fem {

ParamInfo sell_sigma_param() {
    return {"sell-sigma", static_cast<double>(sell_default_sigma),
            "--strategy=sell's sorting window in rows: a positive multiple of C = " + std::to_string(sell_c) +
                ", this build's SIMD width (σ = C keeps the order) (fem-spmv, fem-cg, fem-eigen)"};
}

void validate_sell_sigma(double sigma, const std::string& kernel) {
    if (sigma >= sell_c && sigma <= (1 << 30) && std::fmod(sigma, sell_c) == 0) return;
    throw UsageError("--sell-sigma=" + format_number(sigma) + " for " + kernel + ": accepted: a positive multiple of " +
                     std::to_string(sell_c) + ", this build's SIMD width in doubles (" + std::to_string(sell_c) + ", " +
                     std::to_string(2 * sell_c) + ", " + std::to_string(3 * sell_c) + ", ...)");
}

double SellStorage::footprint_bytes() const {
    return pattern.counts.matrix_bytes() + (m ? 8.0 * static_cast<double>(pattern.counts.stored) : 0.0);
}

SellStorage allocate_sell(Arena& arena, const Pattern& p, int threads, std::int64_t sigma, const double* a,
                          const double* m) {
    SellStorage s;
    try {
        s.pattern.counts = count_sell(p, threads, sigma);
    } catch (const std::invalid_argument& e) {
        throw UsageError(std::string("--strategy=sell: ") + e.what());
    }
    const SellCounts& c = s.pattern.counts;
    s.pattern.chunk_ptr = arena.allocate<std::uint64_t>("sell-chunk-ptr", static_cast<std::size_t>(c.chunks + 1));
    s.pattern.row = arena.allocate<std::uint32_t>("sell-row", static_cast<std::size_t>(c.chunks * sell_c + 1));
    s.pattern.col = arena.allocate<std::uint32_t>("sell-col", c.stored + 1);
    fill_sell(p, s.pattern);
    auto values = [&](const char* name, const double* csr) {
        double* v = arena.allocate<double>(std::string("sell-") + name, c.stored + 1);
        fill_sell_values(p, csr, s.pattern, v);
        return v;
    };
    s.a = values("A", a);
    if (m) s.m = values("M", m);
    return s;
}

void add_sell_facts(const SellStorage& s, std::vector<Fact>& out) {
    const SellCounts& c = s.pattern.counts;
    const double nz = static_cast<double>(c.nnz);
    out.push_back({"sell-bytes-per-nnz", c.matrix_bytes() / nz, "B"});
    out.push_back({"padding", static_cast<double>(c.padding()) / nz, "entries added, of the nonzeros"});
    out.push_back({"sell-c", static_cast<double>(sell_c), "rows a chunk"});
    out.push_back({"sell-sigma", static_cast<double>(c.sigma), "rows a sorting window"});
}

}  // namespace suite::fem
