#include "harness/kernel/permutation.hpp"

#include <random>
#include <utility>

namespace suite {

void shuffled_permutation(std::uint32_t* p, std::uint64_t n, std::uint64_t seed) {
    for (std::uint64_t i = 0; i < n; ++i) p[i] = static_cast<std::uint32_t>(i);
    // std::mt19937_64 is specified bit for bit by the standard; the distribution is not, so the
    // bounded draw is done here (Lemire's multiply-shift, bias below 2^-32 for n < 2^32).
    std::mt19937_64 rng(seed);
    for (std::uint64_t i = n - 1; i > 0; --i) {
        const std::uint64_t j = static_cast<std::uint64_t>((static_cast<unsigned __int128>(rng()) * (i + 1)) >> 64);
        std::swap(p[i], p[j]);
    }
}

}  // namespace suite
