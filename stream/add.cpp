// STREAM add:       for (i = 0; i < n; ++i) a[i] = b[i] + c[i];
// 24 B per element by the STREAM convention (16 read, 8 written), 1 flop.
// With --pattern=random every access goes through the index array, a[p[i]] = b[p[i]] + c[p[i]]:
// the thesis's kernel 3, memory-bound and latency-bound at once.
#include "stream/stream_kernel.hpp"

namespace suite::stream {
namespace {
struct Add {
    static constexpr const char* name = "add";
    static constexpr const char* formula = "a[i] = b[i] + c[i]";
    static constexpr const char* notes = "STREAM add; with --pattern=random the thesis's kernel 3";
    static constexpr int reads = 2;
    static constexpr double flops = 1;
    static constexpr bool has_nt = true;
    static constexpr bool has_rep = false;  // a string-instruction (rep movsb) variant
    static constexpr double tolerance = 0;
    template <class T>
    static T apply(T b, T c) {
        return b + c;
    }
#if SUITE_HAVE_SVE_TWINS
    SUITE_SVE static svfloat64_t apply_sve(svbool_t pg, svfloat64_t b, svfloat64_t c) { return svadd_f64_x(pg, b, c); }
#endif
};
const bool registered = register_stream_kernel<Add>();
}  // namespace
}  // namespace suite::stream
