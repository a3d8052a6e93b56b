// sin-add:          for (i = 0; i < n; ++i) a[i] = sin(b[i]) + sin(c[i]);
// 24 B per element by the STREAM convention, like add, but two sine evaluations per element make
// it compute-bound: the contrast to add that shows whether a loop is limited by memory or by the
// core. flops counts only the addition; the sines are libm calls, not counted as flops.
// With --pattern=random it is the thesis's kernel 4.
#include "stream/stream_kernel.hpp"

namespace suite::stream {
namespace {
struct SinAdd {
    static constexpr const char* name = "sin-add";
    static constexpr const char* formula = "a[i] = sin(b[i]) + sin(c[i])";
    static constexpr const char* notes =
        "compute-bound; 2 sin calls per element (not counted as flops); random = thesis kernel 4";
    static constexpr int reads = 2;
    static constexpr double flops = 1;
    static constexpr bool has_nt = false;
    static constexpr bool has_rep = false;  // a string-instruction (rep movsb) variant
    // A vectorised sine may differ from the scalar one in the last bits.
    static constexpr double tolerance = 1e-13;
    static double apply(double b, double c) { return std::sin(b) + std::sin(c); }
};
const bool registered = register_stream_kernel<SinAdd>();
}  // namespace
}  // namespace suite::stream
