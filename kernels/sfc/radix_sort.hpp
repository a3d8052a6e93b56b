#pragma once
// Stable parallel sort of elements by 64-bit key: afterwards keys[perm[0]] <= keys[perm[1]] <=
// ..., and elements with equal keys stay in their prior (index) order. The sort is the thing
// measured, so it is written here (OpenMP), not taken from a library: one parallel MSD pass on
// the top bits spreads (key, index) pairs into buckets that fit in cache, then each bucket is
// finished by an LSD radix sort of the remaining bits, 8 at a time, skipping the digits that
// are equal within the bucket. Both passes are stable, so the whole is.
#include <cstddef>
#include <cstdint>

namespace suite::sfc {

// Scratch of n entries each, allocated by the caller (through the kernel's Arena).
struct SortBuffers {
    std::uint64_t* keys_a = nullptr;
    std::uint64_t* keys_b = nullptr;
    std::uint32_t* index_a = nullptr;
    std::uint32_t* index_b = nullptr;
};

// Sorts the first `key_bits` bits of `keys` (bits above must be zero) into `perm` (n entries).
// Afterwards buffers.keys_a holds the keys in sorted order. Call outside a parallel region.
void sort_by_key(const std::uint64_t* keys, std::size_t n, int key_bits, std::uint32_t* perm,
                 const SortBuffers& buffers);

}  // namespace suite::sfc
