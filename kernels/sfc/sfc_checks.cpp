#include "kernels/sfc/sfc_checks.hpp"

#include <algorithm>
#include <vector>

namespace suite::sfc {

namespace {

// Whether p[0..n) holds every number 0..n-1 once; otherwise the first position that breaks it.
bool is_permutation(const std::uint32_t* p, std::size_t n, std::size_t& bad) {
    std::vector<char> seen(n, 0);
    for (std::size_t i = 0; i < n; ++i) {
        if (p[i] >= n || seen[p[i]]) {
            bad = i;
            return false;
        }
        seen[p[i]] = 1;
    }
    return true;
}

template <int Dim>
bool key_names_cell(std::uint64_t key, Curve c, int depth, const double* t) {
    std::uint32_t q[3];
    c == Curve::hilbert ? hilbert_decode<Dim>(key, depth, q) : morton_decode<Dim>(key, depth, q);
    for (int a = 0; a < Dim; ++a)
        if (q[a] != quantize(t[a], depth)) return false;
    // Bits above depth * Dim must be zero.
    return Dim * depth == 64 || (key >> (Dim * depth)) == 0;
}

Curve curve_of(Method m) {
    return m == Method::hilbert ? Curve::hilbert : m == Method::morton ? Curve::morton : Curve::morton_recursive;
}

}  // namespace

CheckResult Checks::keys() const {
    const std::size_t ne = in_.elements;
    const int k = in_.dim + 1;
    if (method_ == Method::rcm) {
        CheckResult r{
            true, "RCM vertex numbering a permutation, each key the smallest new number among its element's corners",
            ""};
        std::size_t bad = 0;
        if (!is_permutation(a_.new_id, in_.vertices, bad))
            return {false, r.what, "the RCM numbering is not a permutation (vertex " + std::to_string(bad) + ")"};
        for (std::size_t e = 0; e < ne; ++e) {
            std::uint32_t low = a_.new_id[in_.conn[e * k]];
            for (int j = 1; j < k; ++j) low = std::min(low, a_.new_id[in_.conn[e * k + j]]);
            if (a_.keys[e] != low)
                return {false, r.what,
                        "key of element " + std::to_string(e) + " is " + std::to_string(a_.keys[e]) + ", expected " +
                            std::to_string(low)};
        }
        return r;
    }
    const Curve c = curve_of(method_);
    const std::size_t stride = std::max<std::size_t>(1, ne / 65536);
    const std::string by = method_ == Method::morton_recursive ? "recursive halving" : encoder_name(Encoder::best);
    CheckResult r{true,
                  "keys by " + by + ": every key decoded back to its element's cell at depth " +
                      std::to_string(depth_) + ", " +
                      (stride == 1 ? std::string("every key") : "every " + std::to_string(stride) + "th key") +
                      " recomputed by " +
                      (method_ == Method::morton             ? method_name(Method::morton_recursive)
                       : method_ == Method::morton_recursive ? "the portable morton"
                                                             : "the portable interleave"),
                  ""};
    std::int64_t first_bad = static_cast<std::int64_t>(ne);
    const std::int64_t n = static_cast<std::int64_t>(ne);
#pragma omp parallel for schedule(static) reduction(min : first_bad)
    for (std::int64_t e = 0; e < n; ++e) {
        double t[3];
        unit_position(in_, frame_, static_cast<std::size_t>(e), t);
        const bool ok =
            in_.dim == 2 ? key_names_cell<2>(a_.keys[e], c, depth_, t) : key_names_cell<3>(a_.keys[e], c, depth_, t);
        if (!ok) first_bad = std::min(first_bad, e);
    }
    if (first_bad < n)
        return {false, r.what, "the key of element " + std::to_string(first_bad) + " does not name its cell"};
    const Curve other = method_ == Method::morton             ? Curve::morton_recursive
                        : method_ == Method::morton_recursive ? Curve::morton
                                                              : Curve::hilbert;
    for (std::size_t e = 0; e < ne; e += stride)
        if (element_key(in_, frame_, other, e, Encoder::portable) != a_.keys[e])
            return {false, r.what, "the key of element " + std::to_string(e) + " differs from the other encoder's"};
    return r;
}

CheckResult Checks::sort() const {
    CheckResult r{true, "perm a permutation, keys non-decreasing along it, equal keys in element order", ""};
    const std::size_t ne = in_.elements;
    std::size_t bad = 0;
    if (!is_permutation(a_.perm, ne, bad))
        return {false, r.what, "perm is not a permutation (position " + std::to_string(bad) + ")"};
    for (std::size_t i = 1; i < ne; ++i) {
        const std::uint64_t a = a_.keys[a_.perm[i - 1]], b = a_.keys[a_.perm[i]];
        if (a > b || (a == b && a_.perm[i - 1] > a_.perm[i]))
            return {false, r.what,
                    "positions " + std::to_string(i - 1) + " and " + std::to_string(i) + " are out of order"};
    }
    return r;
}

CheckResult Checks::renumber() const {
    const bool first_touch = method_ != Method::rcm;
    CheckResult r{true,
                  std::string("vertices a permutation") +
                      (first_touch ? " numbered in first-touch order" : " (the RCM numbering)") +
                      ", every element's corners at the same coordinates as before",
                  ""};
    const std::size_t ne = in_.elements, nv = in_.vertices;
    const int k = in_.dim + 1;
    std::size_t bad = 0;
    if (!is_permutation(a_.new_id, nv, bad))
        return {false, r.what, "the vertex numbering is not a permutation (vertex " + std::to_string(bad) + ")"};
    std::uint64_t next = 0;  // the next number a first touch may hand out
    for (std::size_t i = 0; i < ne; ++i) {
        const std::size_t e = a_.perm[i];
        for (int j = 0; j < k; ++j) {
            const std::uint32_t old_v = in_.conn[e * k + j], new_v = a_.out.conn[i * k + j];
            if (new_v != a_.new_id[old_v] || new_v >= nv)
                return {false, r.what,
                        "corner " + std::to_string(j) + " of element " + std::to_string(i) +
                            " is not the renumbered corner of element " + std::to_string(e)};
            bool same = a_.out.x[new_v] == in_.x[old_v] && a_.out.y[new_v] == in_.y[old_v];
            if (in_.dim == 3) same = same && a_.out.z[new_v] == in_.z[old_v];
            if (!same)
                return {false, r.what, "corner " + std::to_string(j) + " of element " + std::to_string(i) + " moved"};
            if (first_touch) {
                if (new_v > next)
                    return {false, r.what, "vertex " + std::to_string(new_v) + " is numbered before its first touch"};
                if (new_v == next) ++next;
            }
        }
    }
    return r;
}

}  // namespace suite::sfc
