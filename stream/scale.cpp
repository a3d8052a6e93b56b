// STREAM scale:     for (i = 0; i < n; ++i) a[i] = s * b[i];      s = 3
// 16 B per element by the STREAM convention (8 read, 8 written), 1 flop.
#include "stream/stream_kernel.hpp"

namespace suite::stream {
namespace {
struct Scale {
    static constexpr const char* name = "scale";
    static constexpr const char* formula = "a[i] = s * b[i]";
    static constexpr const char* notes = "STREAM scale, s = 3";
    static constexpr int reads = 1;
    static constexpr double flops = 1;
    static constexpr bool has_nt = true;
    static constexpr bool has_rep = false;  // a string-instruction (rep movsb) variant
    static constexpr double tolerance = 0;
    template <class T>
    static T apply(T b, T) {
        return scalar * b;
    }
#if SUITE_HAVE_SVE_TWINS
    SUITE_SVE static svfloat64_t apply_sve(svbool_t pg, svfloat64_t b, svfloat64_t) {
        return svmul_n_f64_x(pg, b, scalar);
    }
#endif
};
const bool registered = register_stream_kernel<Scale>();
}  // namespace
}  // namespace suite::stream
