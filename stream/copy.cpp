// STREAM copy:      for (i = 0; i < n; ++i) a[i] = b[i];
// 16 B per element by the STREAM convention (8 read, 8 written), no flops.
#include "stream/stream_kernel.hpp"

namespace suite::stream {
namespace {
struct Copy {
    static constexpr const char* name = "copy";
    static constexpr const char* formula = "a[i] = b[i]";
    static constexpr const char* notes = "STREAM copy";
    static constexpr int reads = 1;
    static constexpr double flops = 0;
    static constexpr bool has_nt = true;
    static constexpr bool has_rep = true;  // a string-instruction (rep movsb) variant
    static constexpr double tolerance = 0;
    template <class T>
    static T apply(T b, T) {
        return b;
    }
#if SUITE_HAVE_SVE_TWINS
    SUITE_SVE static svfloat64_t apply_sve(svbool_t, svfloat64_t b, svfloat64_t) { return b; }
#endif
};
const bool registered = register_stream_kernel<Copy>();
}  // namespace
}  // namespace suite::stream
