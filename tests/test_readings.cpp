// The readings of "the averaged velocity in the channel" (the study's Section 2) measured from a
// field: each test states the property of one reading (diagnostics/flow_diagnostics.hpp,
// fictitious_domain/obstacles.hpp part_velocities).
#include <gtest/gtest.h>

#include <cmath>

#include "diagnostics/flow_diagnostics.hpp"
#include "fictitious_domain/obstacles.hpp"
#include "mesh/channel_mesh.hpp"

using namespace rbc;

namespace {

// u1 = g(y) at every node of the mesh, u2 = 0.
VelocityField field_of(const ChannelMesh& m, double (*g)(double y, double H)) {
  VelocityField u(m);
  for (int j = 0; j <= m.ny; ++j)
    for (int i = 0; i < m.nx; ++i) u.u1[m.v(i, j)] = g(j * m.h, m.height);
  return u;
}

double parabola(double y, double H) { return 4 * y * (H - y) / (H * H); }

}  // namespace

TEST(Readings, NodalMeanWithTheWallRowsIsMOverMPlusOneTimesTheP1MeanOfAnyFieldZeroOnTheWalls) {
  // The trapezoid rule gives the wall rows weight 1/2 and the M − 1 interior rows weight 1; the
  // arithmetic mean counts M + 1 rows: with u = 0 on the walls, U_n = (M/(M+1)) U exactly.
  for (double h : {0.125e-6, 0.3125e-6}) {
    const ChannelMesh m = ChannelMesh::make(20e-6, 10e-6, h);
    const MeanVelocities mv = mean_velocities(m, field_of(m, parabola));
    EXPECT_NEAR(mv.nodal, mv.p1 * m.ny / (m.ny + 1.0), 1e-15 * mv.p1) << "h = " << h;
    // The P1 mean of the nodal parabola 4 y (H − y)/H² is (2/3)(1 − h²/H²): the node sum is right.
    EXPECT_NEAR(mv.p1, 2.0 / 3.0 * (1 - std::pow(h / m.height, 2)), 1e-14);
  }
}

TEST(Readings, EachPartCountsItsPassageWithItsTwoBoundingRows) {
  // Blocks [40, 80] x [0, 7.5] and [40, 80] x [22.5, 30] um in a 120 x 30 um channel (the study's
  // constriction) at h = 0.625 um: a wide section has M + 1 = 49 nodes, a narrow one the 25 of its
  // 15 um passage. With u1 = 1 strictly inside each passage and 0 on its bounding rows, the nodal
  // means are (M − 1)/(M + 1) and (M_n − 1)/(M_n + 1).
  const ChannelMesh m = ChannelMesh::make(120e-6, 30e-6, 0.625e-6);
  const std::vector<Obstacle> blocks = {{{40e-6, 80e-6}, {0.0, 7.5e-6}, "bottom"}, {{40e-6, 80e-6}, {22.5e-6, 30e-6}, "top"}};
  const ObstacleGeometry g(m, blocks);
  VelocityField u(m);
  const double e = 1e-6 * m.h;
  for (int i = 0; i < m.nx; ++i) {
    const bool narrow = g.open_height(m.x(i)) < m.height - e;
    const double lo = narrow ? 7.5e-6 : 0.0, hi = narrow ? 22.5e-6 : m.height;
    for (int j = 0; j <= m.ny; ++j) u.u1[m.v(i, j)] = j * m.h > lo + e && j * m.h < hi - e ? 1.0 : 0.0;
  }
  const PartVelocities pv = part_velocities(g, u);
  const int M = m.ny, Mn = 24;
  EXPECT_NEAR(pv.wide_nodal, (M - 1.0) / (M + 1.0), 1e-14);
  EXPECT_NEAR(pv.narrow_nodal, (Mn - 1.0) / (Mn + 1.0), 1e-14);
  // The flux readings of the same field: (M − 1) h / H and (M_n − 1) h / 15 um (trapezoid).
  EXPECT_NEAR(pv.wide, (M - 1.0) / M, 1e-12);
  EXPECT_NEAR(pv.narrow, (Mn - 1.0) / Mn, 1e-12);
}
