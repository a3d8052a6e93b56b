// The MPM core on small grids: the shape functions, the walk, and a free fall.
#include <gtest/gtest.h>

#include <cmath>

#include "kernels/mesh/generate.hpp"
#include "kernels/mpm/mpm.hpp"

namespace suite::mpm {
namespace {

TEST(MpmGrid, ShapeFunctionsAreOneAtTheirCornerAndZeroAtTheOthers) {
    const Grid g = make_grid(mesh::box_mesh(2, 2, 2));
    for (std::size_t e = 0; e < g.elements(); ++e)
        for (int i = 0; i < 4; ++i) {
            const std::uint32_t v = g.mesh.conn[4 * e + i];
            for (int j = 0; j < 4; ++j) {
                const double* s = &g.shape[16 * e + 4 * j];
                const double n = s[0] + s[1] * g.mesh.x[v] + s[2] * g.mesh.y[v] + s[3] * g.mesh.z[v];
                EXPECT_NEAR(n, i == j ? 1.0 : 0.0, 1e-12) << "element " << e << " corner " << i << " function " << j;
            }
        }
}

TEST(MpmFreeFall, VelocityIsGTimesTAwayFromTheWalls) {
    Settings s;
    s.region = {{0.35, 0.35, 0.6}, {0.65, 0.65, 0.9}};
    State st = make_state(make_grid(mesh::box_mesh(8, 8, 8)), s, Strategy::serial, 1);
    const double m0 = totals(st.particles).mass;
    for (int k = 0; k < 20; ++k) step(st);
    const double v = s.gravity[2] * st.time;
    for (std::size_t p = 0; p < st.particles.size(); ++p) {
        EXPECT_NEAR(st.particles.vz[p], v, 1e-12 * std::fabs(v));
        EXPECT_NEAR(st.particles.vx[p], 0, 1e-12);
    }
    EXPECT_DOUBLE_EQ(totals(st.particles).mass, m0);
}

}  // namespace
}  // namespace suite::mpm
