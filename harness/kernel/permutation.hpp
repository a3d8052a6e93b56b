#pragma once
// The seeded random order that every random pattern and ordering uses (the stream kernels'
// index array, the sfc "random" ordering), the same on every machine for the same seed.
#include <cstdint>

namespace suite {

// A seeded uniformly random permutation of 0..n-1 (Fisher-Yates with a fixed generator, so the
// same seed gives the same permutation on every machine). Filled into already-touched memory.
void shuffled_permutation(std::uint32_t* p, std::uint64_t n, std::uint64_t seed);

}  // namespace suite
