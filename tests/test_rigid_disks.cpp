// Freely moving neutrally buoyant rigid disks by the fictitious domain (lib/fictitious_domain/
// rigid_disks.hpp; Glowinski, Pan, Hesla & Joseph 1999). Each test can fail: the bounds are
// measured values with a stated margin (numbers in the comments).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>

#include "fictitious_domain/rigid_disks.hpp"
#include "fluid/channel_flow.hpp"
#include "scene/simulation.hpp"

namespace rbc {
namespace {

ChannelFlowParams channel(double L, double H, double h, double dt) {
  ChannelFlowParams p;
  p.length = L;
  p.height = H;
  p.mesh_size = h;
  p.dt = dt;
  return p;  // the study's Lie form of the pressure (the incremental one is not fit for disks: below)
}

// A sheared, swirling right-hand side of step 4 (both components, interior rows).
std::array<std::vector<double>, 2> sheared_rhs(const ChannelMesh& m, const ChannelFlowParams& p) {
  const int nx = m.nx, rows = m.ny - 1;
  std::array<std::vector<double>, 2> b = {std::vector<double>(std::size_t(nx) * rows), std::vector<double>(std::size_t(nx) * rows)};
  for (int r = 0; r < rows; ++r)
    for (int i = 0; i < nx; ++i) {
      const double x = i * m.h, y = (r + 1) * m.h;
      b[0][std::size_t(r) * nx + i] = 1e-3 * (y / p.height) + 2e-4 * std::sin(2 * M_PI * x / p.length);
      b[1][std::size_t(r) * nx + i] = 3e-4 * std::cos(2 * M_PI * y / p.height) * std::sin(4 * M_PI * x / p.length);
    }
  return b;
}

// max |u − R q| over the disk's collocation points, over max |u| (step 4's result u).
double rigid_defect(const DiskConstraint& dc, const std::array<std::vector<double>, 2>& u) {
  const Eigen::Vector3d q = dc.motion()[0];
  double worst = 0, scale = 0;
  for (int c = 0; c < 2; ++c)
    for (double v : u[std::size_t(c)]) scale = std::max(scale, std::abs(v));
  const DiskPoints& pts = dc.points()[0];
  auto rigid = [&](int c, const Eigen::Vector2d& o) { return c == 0 ? q[0] - q[2] * o.y() : q[1] + q[2] * o.x(); };
  for (std::size_t c = 0; c < 2; ++c) {
    for (const auto& pt : pts.ring) {
      double s = 0;
      for (int a = 0; a < pt.count; ++a) s += pt.weights[std::size_t(a)] * u[c][std::size_t(pt.nodes[std::size_t(a)])];
      worst = std::max(worst, std::abs(s - rigid(int(c), pt.offset)));
    }
    for (const auto& pt : pts.deep) worst = std::max(worst, std::abs(u[c][std::size_t(pt.nodes[0])] - rigid(int(c), pt.offset)));
  }
  return worst / scale;
}

// Step 4 with a disk: after the solve the velocity at every collocation point is the rigid motion
// V + ω × (x − G) to the tolerance, and the multiplier's net force and torque vanish (neutrally
// buoyant): A u − b, summed over the grid with and without the lever arm.
TEST(RigidDisks, StepFourHoldsTheDiskRigidWithNoNetForceOrTorque) {
  const ChannelFlowParams p = channel(20e-6, 20e-6, 0.25e-6, 2e-6);
  ChannelFlow flow(p);
  const ChannelMesh& m = flow.mesh();
  DiskConstraint dc(m, flow.diffusion().helmholtz(), p.fluid.density, p.dt, 1e-10);
  Disk d;
  d.center = {9.3e-6, 10.6e-6};
  d.radius = 2.8e-6;
  dc.set_disks({d});
  const int nx = m.nx, rows = m.ny - 1;
  const std::array<std::vector<double>, 2> b = sheared_rhs(m, p);
  std::array<std::vector<double>, 2> u = b;
  dc.solve_pair(u[0].data(), u[1].data());
  const Eigen::Vector3d q = dc.motion()[0];
  const DiskPoints& pts = dc.points()[0];
  const double worst = rigid_defect(dc, u);
  std::printf("[ measured ] %zu ring points, %zu deep nodes; defect %.2e of max |u| after %d iteration(s); V = (%.3e, %.3e) m/s, omega = %.3e 1/s\n",
              pts.ring.size(), pts.deep.size(), worst, dc.last().iterations, q[0], q[1], q[2]);
  EXPECT_LE(worst, 1e-10);
  EXPECT_EQ(dc.last().iterations, 1);  // one disk: its capacitance system is the whole system
  // Net force and torque of the multiplier: f = A u − b at every node.
  const double diag = p.fluid.density * m.h * m.h / p.dt + 4 * p.fluid.viscosity, mu = p.fluid.viscosity;
  Eigen::Vector3d net = Eigen::Vector3d::Zero();
  double total = 0;
  for (int r = 0; r < rows; ++r)
    for (int i = 0; i < nx; ++i) {
      const std::size_t k = std::size_t(r) * nx + i;
      double f[2];
      for (int c = 0; c < 2; ++c) {
        double s = diag * u[c][k] - mu * (u[c][std::size_t(r) * nx + m.wrap(i - 1)] + u[c][std::size_t(r) * nx + m.wrap(i + 1)]);
        if (r > 0) s -= mu * u[c][k - nx];
        if (r + 1 < rows) s -= mu * u[c][k + nx];
        f[c] = s - b[c][k];
      }
      double ox = i * m.h - d.center.x();
      ox = nearest_image(ox, p.length);
      const double oy = (r + 1) * m.h - d.center.y();
      net += Eigen::Vector3d(f[0], f[1], ox * f[1] - oy * f[0]);
      total += std::abs(f[0]) + std::abs(f[1]);
    }
  std::printf("[ measured ] net force (%.2e, %.2e), net torque / r %.2e, of the multiplier's total %.2e\n", net[0] / total, net[1] / total,
              net[2] / d.radius / total, total);
  EXPECT_LE(std::abs(net[0]) / total, 1e-10);
  EXPECT_LE(std::abs(net[1]) / total, 1e-10);
  EXPECT_LE(std::abs(net[2]) / d.radius / total, 1e-10);
}

// The boundary's collocation points about s h apart ([solver] disk_boundary_spacing): an even
// count of at least 8 near 2πr/(s h), and step 4 still holds the disk rigid on all of them at 2
// and 4 h (half and a quarter of the method's points). At 0.5 h (two points a mesh cell) the
// points over-determine the multiplier and the disk's capacitance matrix is refused as singular.
TEST(RigidDisks, BoundaryPointsFollowTheirSpacingAndStepFourStaysRigid) {
  const ChannelFlowParams p = channel(20e-6, 20e-6, 0.25e-6, 2e-6);
  ChannelFlow flow(p);
  const ChannelMesh& m = flow.mesh();
  Disk d;
  d.center = {9.3e-6, 10.6e-6};
  d.radius = 2.8e-6;
  EXPECT_EQ(boundary_point_count(d.radius, m.h, 1.0), 72);  // 2π 2.8/0.25 = 70.4 -> 71 -> even
  EXPECT_EQ(boundary_point_count(0.3e-6, m.h, 4.0), 8);     // at least 8
  {
    DiskConstraint dense(m, flow.diffusion().helmholtz(), p.fluid.density, p.dt, 1e-10, DiskConstraint::kMaxIterations, 0.5);
    EXPECT_THROW(dense.set_disks({d}), std::runtime_error);
  }
  for (double spacing : {4.0, 2.0}) {
    DiskConstraint dc(m, flow.diffusion().helmholtz(), p.fluid.density, p.dt, 1e-10, DiskConstraint::kMaxIterations, spacing);
    dc.set_disks({d});
    const int expected = boundary_point_count(d.radius, m.h, spacing);
    EXPECT_EQ(expected % 2, 0);
    EXPECT_NEAR(expected, 2 * M_PI * d.radius / (spacing * m.h), 2.0);
    const auto& ring = dc.points()[0].ring;
    EXPECT_EQ(std::count_if(ring.begin(), ring.end(), [](const DiskPoints::Point& pt) { return pt.count == 4; }), expected);
    std::array<std::vector<double>, 2> u = sheared_rhs(m, p);
    dc.solve_pair(u[0].data(), u[1].data());
    const double defect = rigid_defect(dc, u);
    std::printf("[ measured ] spacing %g h: %d boundary points, defect %.2e of max |u|\n", spacing, expected, defect);
    EXPECT_LE(defect, 1e-10);
  }
}

// A disk at mid-height of a plane shear flow (walls at ∓U) stays there and spins at −γ̇/2, the
// value for a free cylinder in unbounded Stokes shear, less the effect of the walls and of the
// periodic images (2r/H = 0.2, period L = H): measured ω/(−γ̇/2) = 0.98867 at h = r/8
// and 0.98770 at h = r/16, so the 1.2 % is the geometry's and the mesh moves it by 0.1 %; the
// bounds: 2 % for the geometry (1.6 times the measured 1.2 %), 0.5 % between the two meshes. (With the incremental pressure form
// 0.98013 and 0.97877.) The centre does not move at all: the boundary points are symmetric under
// the half turn about it (with an odd count it drifted 3 nm in 1 ms).
TEST(RigidDisks, DiskInShearFlowStaysAtMidHeightAndSpinsAtHalfTheShearRate) {
  auto spin = [](double h, double H, Eigen::Vector2d* centre) {
    const double U = 0.01, shear = 2 * U / H, dt = 1e-6;
    ChannelFlowParams p = channel(20e-6, H, h, dt);
    p.wall_velocity[0] = -U;
    p.wall_velocity[1] = U;
    ChannelFlow flow(p);
    const ChannelMesh& m = flow.mesh();
    for (int j = 0; j <= m.ny; ++j)
      for (int i = 0; i < m.nx; ++i) flow.velocity().u1[m.v(i, j)] = -U + shear * j * m.h;
    DiskConstraint dc(m, flow.diffusion().helmholtz(), p.fluid.density, p.dt, 1e-10);
    flow.diffusion().set_constraint(&dc);
    Disk d;
    d.center = {10e-6, H / 2};
    d.radius = 2e-6;
    const int steps = int(std::lround(3 * p.fluid.density * H * H / p.fluid.viscosity / dt));  // three viscous times
    for (int s = 0; s < steps; ++s) {
      dc.set_disks({d});
      flow.step();
      const Eigen::Vector3d q = dc.motion()[0];
      d.velocity = q.head<2>();
      d.angular_velocity = q[2];
      d.center += dt * d.velocity;
      d.angle += dt * q[2];
    }
    *centre = d.center;
    const double ratio = d.angular_velocity / (-shear / 2);
    std::printf("[ measured ] h = %.4g um, 2r/H = %.2f: centre moved (%.2e, %.2e) um, omega / (-shear/2) = %.5f\n", h * 1e6, 4e-6 / H,
                (d.center.x() - 10e-6) * 1e6, (d.center.y() - H / 2) * 1e6, ratio);
    return ratio;
  };
  Eigen::Vector2d c;
  const double coarse = spin(0.25e-6, 20e-6, &c);
  EXPECT_NEAR(c.y(), 10e-6, 1e-12);
  EXPECT_NEAR(c.x(), 10e-6, 1e-12);
  const double fine = spin(0.125e-6, 20e-6, &c);
  EXPECT_NEAR(c.y(), 10e-6, 1e-12);
  EXPECT_NEAR(coarse, 1.0, 0.02);
  EXPECT_NEAR(fine, 1.0, 0.02);
  EXPECT_NEAR(coarse, fine, 5e-3);
}

// Segré–Silberberg: a neutrally buoyant disk in plane Poiseuille flow drifts across the flow
// toward an equilibrium height between the wall and the centreline: up from near the wall, down
// from near the centreline. Through the Simulation (the disks' predicted position, the study's Lie
// form of the pressure): 20 x 20 um channel, Re0 = 2 (mean speed 0.12 m/s), disk radius 2 um
// (2r/H = 0.2), h = 0.25 um, Δt = 1e-6 s (Q = 2), from the developed flow, for 1 ms. In Stokes
// flow a neutrally buoyant disk would not drift at all (reversibility): the drift is inertia's.
// Measured (the printout): from 3.5 um up by 0.17 um, from 8.5 um down by 0.08 um
// (with the lagged position and Δt = 2e-7 s: +0.18 and −0.11 um: Δt-independent). The pressure's
// incremental form ([time] projection = "incremental") is NOT fit for disks: its lagged pressure
// pushes a spinning, moving disk sideways at ≈ ω V Δt (at Δt = 1e-6 s this turned the near-centre
// disk's drift inward; in the study's wide channel 0.60, 0.28, 0.15 um in 2 ms at Δt = 2, 1,
// 0.5 us against 0.065, 0.070, 0.073 um with the study's form).
TEST(RigidDisks, DiskInPoiseuilleFlowDriftsTowardAnEquilibriumBetweenWallAndCentreline) {
  auto drift = [](double y0) {
    Scene s;
    s.source = "test_rigid_disks poiseuille";
    s.length = 20e-6;
    s.height = 20e-6;
    s.mesh_size = 0.25e-6;
    s.reynolds0 = 2.0;
    s.dt = 1e-6;
    s.end = 1e-3;
    s.advection_substeps = 2;
    s.disks = {{{10e-6, y0}, 2e-6}};
    Simulation sim(s);
    sim.start_from_cell_free_profile();
    for (long n = 0; n < 1000; ++n) {
      sim.step();
      sim.check_health();
    }
    const Disk& d = sim.disks()[0];
    std::printf("[ measured ] from y = %.2f um: y = %.4f um after 1 ms (V2 = %.3e m/s, V1 = %.4e m/s)\n", y0 * 1e6, d.center.y() * 1e6,
                d.velocity.y(), d.velocity.x());
    return d.center.y() - y0;
  };
  const double near_wall = drift(3.5e-6), near_centre = drift(8.5e-6);
  EXPECT_GT(near_wall, 0.0);
  EXPECT_LT(near_centre, 0.0);
}

}  // namespace
}  // namespace rbc

namespace rbc {
namespace {

// The contact force (Simulation::contact_forces, [contact] range 2h, strength 1e-3 N/m): a disk
// placed 1.5h off the bottom wall, and (another run) two disks 1.5h apart, in a fluid at rest
// without a body force, are pushed apart: the gaps grow and the force falls (as (range − gap)²,
// so the gap nears the range ever more slowly). The two disks, placed symmetrically about a mesh
// line, move apart with opposite velocities. Measured: wall gap 1.5, 1.86, 1.94 h and
// pair gap 1.5, 1.90, 1.96 h at 0, 0.1, 0.3 ms; |V_0 + V_1| / max |V_0| = 9.9e-15.
TEST(RigidDisks, ContactForcePushesDisksOffTheWallAndApart) {
  auto run = [](const std::vector<DiskSpec>& disks, std::vector<double>* gaps, double* asymmetry, long* contact_steps) {
    Scene s;
    s.source = "test_rigid_disks contact";
    s.length = 24e-6;
    s.height = 10e-6;
    s.mesh_size = 0.25e-6;
    s.body_force = 0.0;
    s.dt = 1e-6;
    s.end = 3e-4;
    s.disks = disks;
    Simulation sim(s);
    auto gap = [&](const std::vector<Disk>& d) { return d.size() == 1 ? d[0].center.y() - d[0].radius : d[1].center.x() - d[0].center.x() - d[0].radius - d[1].radius; };
    double worst = 0, peak = 0;
    gaps->push_back(gap(sim.disks()));
    for (long n = 0; n < std::lround(s.end / s.dt); ++n) {
      sim.step();
      sim.check_health();
      const auto& d = sim.disks();
      if (n == 99 || n == 299) gaps->push_back(gap(d));
      if (d.size() == 2) {
        peak = std::max(peak, std::abs(d[0].velocity.x()));
        worst = std::max(worst, std::abs(d[0].velocity.x() + d[1].velocity.x()) + std::abs(d[0].velocity.y() + d[1].velocity.y()));
      }
    }
    *asymmetry = peak > 0 ? worst / peak : 0;
    *contact_steps = sim.contact_steps();
    return sim.contact_forces();
  };
  const double r = 1.5e-6, h = 0.25e-6, gap = 1.5 * h;
  std::vector<double> wall, pair;
  double asym_wall = 0, asym_pair = 0;
  long steps_wall = 0, steps_pair = 0;
  const auto f_wall = run({{{5e-6, r + gap}, r}}, &wall, &asym_wall, &steps_wall);
  const auto f_pair = run({{{12e-6 - r - gap / 2, 5e-6}, r}, {{12e-6 + r + gap / 2, 5e-6}, r}}, &pair, &asym_pair, &steps_pair);
  std::printf("[ measured ] wall gap %.4f, %.4f, %.4f h at 0, 0.1, 0.3 ms (force now %.2e N/m, %ld steps with contact)\n", wall[0] / h,
              wall[1] / h, wall[2] / h, f_wall[0].norm(), steps_wall);
  std::printf("[ measured ] pair gap %.4f, %.4f, %.4f h (force now %.2e N/m, %ld steps); |V_0 + V_1| / max |V_0| = %.2e\n", pair[0] / h,
              pair[1] / h, pair[2] / h, f_pair[0].norm(), steps_pair, asym_pair);
  for (const auto* g : {&wall, &pair}) {
    EXPECT_GT((*g)[1], (*g)[0] + 0.1 * h);
    EXPECT_GT((*g)[2], (*g)[1]);
    EXPECT_LT((*g)[2], 2 * h);
  }
  EXPECT_EQ(steps_wall, 300);
  EXPECT_LT(f_wall[0].norm(), 1e-3 * 0.25 * 0.25);  // below its start, (0.5h / 2h)² of the strength
  EXPECT_NEAR(f_pair[0].norm(), f_pair[1].norm(), 1e-20);
  EXPECT_LE(asym_pair, 1e-8);
}

}  // namespace
}  // namespace rbc
