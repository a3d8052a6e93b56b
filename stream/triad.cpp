// STREAM triad:     for (i = 0; i < n; ++i) a[i] = b[i] + s * c[i];      s = 3
// 24 B per element by the STREAM convention (16 read, 8 written), 2 flops.
#include "stream/stream_kernel.hpp"

namespace suite::stream {
namespace {
struct Triad {
    static constexpr const char* name = "triad";
    static constexpr const char* formula = "a[i] = b[i] + s * c[i]";
    static constexpr const char* notes = "STREAM triad, s = 3";
    static constexpr int reads = 2;
    static constexpr double flops = 2;
    static constexpr bool has_nt = true;
    static constexpr bool has_rep = false;  // a string-instruction (rep movsb) variant
    static constexpr double tolerance = 0;
    template <class T>
    static T apply(T b, T c) {
        return b + scalar * c;
    }
#if SUITE_HAVE_SVE_TWINS
    SUITE_SVE static svfloat64_t apply_sve(svbool_t pg, svfloat64_t b, svfloat64_t c) {
        return svmla_n_f64_x(pg, b, c, scalar);
    }
#endif
};
const bool registered = register_stream_kernel<Triad>();
}  // namespace
}  // namespace suite::stream
