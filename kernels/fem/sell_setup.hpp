#pragma once
// SELL-C-σ in the solver kernels (fem_solve.cpp): its parameter --sell-sigma and its check, its
// arrays from the kernel's arena, and the facts of its record. sell.hpp has the storage itself.
#include <string>
#include <vector>

#include "harness/kernel/kernel.hpp"
#include "kernels/fem/sell.hpp"

namespace suite::fem {

ParamInfo sell_sigma_param();
// Throws UsageError naming the accepted values unless σ is a positive multiple of C.
void validate_sell_sigma(double sigma, const std::string& kernel);

// The storage of A and, where m is not null, of M on the same structure: allocated from the
// arena and first touched by the team of `threads`, each thread its own chunks.
struct SellStorage {
    SellPattern pattern;
    const double* a = nullptr;
    const double* m = nullptr;
    // Bytes of the arrays (the structure once, the values of each matrix): the footprint's share.
    double footprint_bytes() const;
};
SellStorage allocate_sell(Arena& arena, const Pattern& p, int threads, std::int64_t sigma, const double* a,
                          const double* m);

// sell-bytes-per-nnz, padding (entries added, of the nonzeros), sell-c, sell-sigma.
void add_sell_facts(const SellStorage& s, std::vector<Fact>& out);

}  // namespace suite::fem
