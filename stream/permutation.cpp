// What the stream kernels share outside their loops: the random permutation and the checks
// of a configuration.
#include <random>

#include "stream/stream_kernel.hpp"

namespace suite::stream {

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

void validate_stream_config(const KernelConfig& cfg, const char* name, int arrays) {
    const std::uint64_t n = stream_elements(cfg, arrays);
    const std::uint64_t threads = static_cast<std::uint64_t>(cfg.threads);
    if (n < 2 * threads)
        throw UsageError("size " + format_bytes(cfg.size) + " is too small for " + name + " with " + std::to_string(threads) +
                         " thread(s); use at least " + format_bytes(2 * threads * (8 * arrays + 4)));
    if (cfg.access.name == "random" && n > UINT32_MAX)
        throw UsageError("size " + format_bytes(cfg.size) + " is too large for the random pattern, whose index array holds 32-bit "
                         "indices (at most 4294967295 elements); use a smaller size");
    if (cfg.access.name == "strided" && n < cfg.access.stride * threads)
        throw UsageError("--pattern=" + cfg.access.label() + " with " + std::to_string(threads) + " thread(s) needs at least " +
                         std::to_string(cfg.access.stride) + " elements per thread; use a size of at least " +
                         format_bytes(cfg.access.stride * threads * 8 * arrays));
    if (cfg.variant == "nt" && cfg.access.name != "sequential")
        throw UsageError("--stores=nt works with --pattern=sequential only, not '" + cfg.access.label() + "'");
}

}  // namespace suite::stream
