#include "kernels/mesh/mesh.hpp"

#include <algorithm>
#include <cmath>

namespace suite::mesh {

double signed_measure(const MeshView& m, std::size_t e) {
    const std::uint32_t* c = m.conn + e * static_cast<std::size_t>(m.dim + 1);
    if (m.dim == 2) {
        const double ax = m.x[c[1]] - m.x[c[0]], ay = m.y[c[1]] - m.y[c[0]];
        const double bx = m.x[c[2]] - m.x[c[0]], by = m.y[c[2]] - m.y[c[0]];
        return ax * by - ay * bx;
    }
    double d[3][3];
    for (int k = 0; k < 3; ++k) {
        d[k][0] = m.x[c[k + 1]] - m.x[c[0]];
        d[k][1] = m.y[c[k + 1]] - m.y[c[0]];
        d[k][2] = m.z[c[k + 1]] - m.z[c[0]];
    }
    return d[0][0] * (d[1][1] * d[2][2] - d[1][2] * d[2][1]) - d[0][1] * (d[1][0] * d[2][2] - d[1][2] * d[2][0]) +
           d[0][2] * (d[1][0] * d[2][1] - d[1][1] * d[2][0]);
}

bool degenerate(const MeshView& m, std::size_t e) {
    const int k = m.dim + 1;
    const std::uint32_t* c = m.conn + e * static_cast<std::size_t>(k);
    double longest = 0;
    for (int i = 0; i < k; ++i)
        for (int j = i + 1; j < k; ++j) {
            if (c[i] == c[j]) return true;
            double d2 =
                (m.x[c[i]] - m.x[c[j]]) * (m.x[c[i]] - m.x[c[j]]) + (m.y[c[i]] - m.y[c[j]]) * (m.y[c[i]] - m.y[c[j]]);
            if (m.dim == 3) d2 += (m.z[c[i]] - m.z[c[j]]) * (m.z[c[i]] - m.z[c[j]]);
            longest = std::max(longest, d2);
        }
    // Rounding leaves a few ulps of the products in the determinant of a flat element, so an
    // exact zero test would let nearly all flat elements through.
    const double scale = m.dim == 2 ? longest : longest * std::sqrt(longest);
    return !(std::fabs(signed_measure(m, e)) > 1e-13 * scale);
}

std::string element_word(int dim, bool plural) {
    return std::string(dim == 2 ? "triangle" : "tetrahedr") + (dim == 2 ? (plural ? "s" : "") : (plural ? "a" : "on"));
}

}  // namespace suite::mesh
