// The checks of a stream kernel's configuration, run for every point before anything is measured.
#include "stream/stream_kernel.hpp"

namespace suite::stream {

void validate_stream_config(const KernelConfig& cfg, const char* name, int arrays) {
    const std::uint64_t n = stream_elements(cfg, arrays);
    const std::uint64_t threads = static_cast<std::uint64_t>(cfg.threads);
    if (n < 2 * threads)
        throw UsageError("size " + format_bytes(cfg.size) + " is too small for " + name + " with " +
                         std::to_string(threads) + " thread(s); use at least " +
                         format_bytes(2 * threads * (8 * arrays + 4)));
    if (pattern_of(cfg.access) == Pattern::random && n > UINT32_MAX)
        throw UsageError("size " + format_bytes(cfg.size) +
                         " is too large for the random pattern, whose index array holds 32-bit "
                         "indices (at most 4294967295 elements); use a smaller size");
    if (pattern_of(cfg.access) == Pattern::strided && n < cfg.access.stride * threads)
        throw UsageError("--pattern=" + cfg.access.label() + " with " + std::to_string(threads) +
                         " thread(s) needs at least " + std::to_string(cfg.access.stride) +
                         " elements per thread; use a size of at least " +
                         format_bytes(cfg.access.stride * threads * 8 * arrays));
    if (is_store_variant(cfg.variant) && pattern_of(cfg.access) != Pattern::sequential)
        throw UsageError("--stores=" + cfg.variant + " works with --pattern=" + pattern_name(Pattern::sequential) +
                         " only, not '" + cfg.access.label() + "'");
}

}  // namespace suite::stream
