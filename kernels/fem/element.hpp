#pragma once
// The P1 triangle of the Helmholtz waveguide problem -Δu - k²u = λu on the unit disk (Neumann):
//   k²(x, y) = (100 + δ) exp(-50 (x² + y²)) - 100
//   A_e(i, j) = |T| ∇φi·∇φj - Σ_q (|T|/3) k²(x_q) φi(x_q) φj(x_q)   (3-point Gauss rule, degree 2)
//   M_e(i, j) = |T|/12 (1 + δij)                                      (exact)
// The element loop of every assembly strategy calls element_matrices(), so that they differ only
// in how they add the result into the global matrices.
#include <cmath>

namespace suite::fem {

inline double k_squared(double x, double y, double delta) {
    return (100.0 + delta) * std::exp(-50.0 * (x * x + y * y)) - 100.0;
}

// The Gauss points of the rule, in barycentric coordinates: point q has weight 2/3 on corner q
// and 1/6 on the others. Exact for polynomials of degree 2, so for the mass term of a constant k².
constexpr double gauss_major = 2.0 / 3.0, gauss_minor = 1.0 / 6.0;

// Row-major 3x3 local matrices of the triangle with corners (x[i], y[i]). Orientation does not
// matter: the area is |det|/2.
struct ElementMatrices {
    double a[9];
    double m[9];
};

// Floating-point operations of one call, counted by hand from the code below (an exp as one,
// the Gauss point products as the compiler folds them): 16 for the geometry and the mass, 20 per
// Gauss point, 11 per entry of A: 175 in all.
constexpr double element_flops = 175;

inline void element_matrices(const double x[3], const double y[3], double delta, ElementMatrices& out) {
    const double x10 = x[1] - x[0], x20 = x[2] - x[0], y10 = y[1] - y[0], y20 = y[2] - y[0];
    const double det = x10 * y20 - x20 * y10;
    const double area = 0.5 * std::fabs(det);
    // ∇φ of the three corners, times det: (y1 - y2, x2 - x1), (y2 - y0, x0 - x2), (y0 - y1, x1 - x0).
    const double gx[3] = {y[1] - y[2], y20, -y10}, gy[3] = {x[2] - x[1], -x20, x10};
    const double stiff = area / (det * det);
    // k² at the Gauss points, each weighted |T|/3.
    double kw[3];
    for (int q = 0; q < 3; ++q) {
        const double px = gauss_minor * (x[0] + x[1] + x[2]) + (gauss_major - gauss_minor) * x[q];
        const double py = gauss_minor * (y[0] + y[1] + y[2]) + (gauss_major - gauss_minor) * y[q];
        kw[q] = (area / 3.0) * k_squared(px, py, delta);
    }
    const double mass = area / 12.0;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
            // Σ_q w_q k² φi φj with φi(x_q) = 2/3 if i == q else 1/6.
            double kterm = 0;
            // (φi φj) first, so that A_e(i, j) and A_e(j, i) round alike: the matrix is exactly symmetric.
            for (int q = 0; q < 3; ++q)
                kterm += kw[q] * ((i == q ? gauss_major : gauss_minor) * (j == q ? gauss_major : gauss_minor));
            out.a[3 * i + j] = stiff * (gx[i] * gx[j] + gy[i] * gy[j]) - kterm;
            out.m[3 * i + j] = i == j ? 2 * mass : mass;
        }
}

}  // namespace suite::fem
