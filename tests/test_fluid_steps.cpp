// Properties of the study's fluid steps (its Sec. 2.4; paper/method/01_fluid_steps.md): each test
// names the property.
#include <gtest/gtest.h>
#include <omp.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <numbers>
#include <random>
#include <vector>

#include <Eigen/Core>

#include "diagnostics/flow_diagnostics.hpp"
#include "fluid/channel_flow.hpp"
#include "fluid/detail/advection_kernels.hpp"
#include "semi_implicit/coupling_products.hpp"

namespace rbc {
namespace {

constexpr double kPi = std::numbers::pi;

// The study's narrow channel (its Sec. 3.1.1) on a coarser mesh, so that the test is quick.
ChannelFlowParams narrow_channel(double h, double dt) {
  ChannelFlowParams p;
  p.length = 20e-6;
  p.height = 10e-6;
  p.mesh_size = h;
  p.dt = dt;
  p.body_force = body_force_from_reynolds(0.5556, p.fluid, p.height);
  return p;
}

double max_profile_error(const ChannelFlow& flow, const std::function<double(double)>& exact) {
  const ChannelMesh& m = flow.mesh();
  if (!all_finite(flow.velocity())) return INFINITY;
  double e = 0;
  for (int j = 0; j <= m.ny; ++j)
    for (int i = 0; i < m.nx; ++i) {
      e = std::max(e, std::abs(flow.velocity().u1[m.v(i, j)] - exact(m.y(j))));
      e = std::max(e, std::abs(flow.velocity().u2[m.v(i, j)]));
    }
  return e;
}

TEST(PoiseuilleFlow, BodyForceFromReynoldsGivesTheStudysMeanVelocity) {
  // U0 = Re0 μ/(ρ H) = 6.667 cm/s in every experiment (reference-data/README.md).
  const ChannelFlowParams p = narrow_channel(0.5e-6, 1e-7);
  const double u0 = p.body_force * p.height * p.height / (12 * p.fluid.viscosity);
  EXPECT_NEAR(u0, 0.066672, 1e-9);
}

TEST(PoiseuilleFlow, SteadyStateFromRestIsTheParabolaAtTheNodes) {
  // The 5-point Laplacian differentiates quadratics exactly, so the discrete steady state is the
  // parabola f x2 (H − x2)/(2μ) at the nodes; its P1 mean (trapezoid rule) is U0 (1 − h²/H²).
  const ChannelFlowParams p = narrow_channel(0.5e-6, 2e-7);
  ChannelFlow flow(p);
  const double H = p.height, f = p.body_force, mu = p.fluid.viscosity;
  // The slowest mode decays like exp(−π² ν t / H²); 3e-4 s leaves less than 1e-13 of it.
  while (flow.time() < 3e-4) flow.step();
  const double peak = f * H * H / (8 * mu);
  EXPECT_LT(max_profile_error(flow, [&](double y) { return f * y * (H - y) / (2 * mu); }), 1e-10 * peak);
  const double u0 = f * H * H / (12 * mu);
  const double hH = p.mesh_size / H;
  EXPECT_NEAR(mean_velocity(flow.mesh(), flow.velocity()), u0 * (1 - hH * hH), 1e-10 * u0);
}

TEST(PoiseuilleFlow, ParabolaIsAFixedPointOfTheLieStep) {
  ChannelFlow flow(narrow_channel(0.5e-6, 1e-7));
  flow.set_poiseuille();
  const VelocityField u0 = flow.velocity();
  for (int n = 0; n < 20; ++n) flow.step();
  double e = 0;
  for (std::size_t k = 0; k < u0.u1.size(); ++k) e = std::max(e, std::abs(flow.velocity().u1[k] - u0.u1[k]));
  EXPECT_LT(e, 1e-12 * max_speed(u0));
}

// Start-up of plane Poiseuille flow from rest (the Fourier-series solution):
//   u(y, t) = f y (H − y)/(2μ) − Σ_{n odd} 4 f H²/(μ π³ n³) sin(nπy/H) exp(−n²π² ν t / H²).
double startup_exact(double y, double t, double f, double H, double mu, double nu) {
  double u = f * y * (H - y) / (2 * mu);
  for (int n = 1; n < 400; n += 2)
    u -= 4 * f * H * H / (mu * kPi * kPi * kPi * n * n * n) * std::sin(n * kPi * y / H) *
         std::exp(-n * n * kPi * kPi * nu * t / (H * H));
  return u;
}

TEST(PoiseuilleFlow, StartupFromRestConvergesToFourierSeriesFirstOrderInTime) {
  // Backward Euler in time: the error at fixed t halves with Δt (order 1); the spatial error of
  // the 5-point Laplacian at h = H/40 is far below the time error at these Δt.
  const double t_end = 2e-5;
  std::vector<double> err;
  for (double dt : {4e-7, 2e-7, 1e-7}) {
    const ChannelFlowParams p = narrow_channel(0.25e-6, dt);
    ChannelFlow flow(p);
    for (long n = 0, steps = std::lround(t_end / dt); n < steps; ++n) flow.step();
    const double nu = p.fluid.viscosity / p.fluid.density;
    err.push_back(max_profile_error(flow, [&](double y) {
      return startup_exact(y, flow.time(), p.body_force, p.height, p.fluid.viscosity, nu);
    }));
  }
  const double order1 = std::log2(err[0] / err[1]), order2 = std::log2(err[1] / err[2]);
  EXPECT_NEAR(order1, 1.0, 0.15);
  EXPECT_NEAR(order2, 1.0, 0.15);
  EXPECT_LT(err[2], 0.01 * 0.1);  // below 1 % of the 0.1 m/s peak at the finest Δt
}

TEST(PoiseuilleFlow, StartupFromRestConvergesSecondOrderInTimeInBdf2Form) {
  // The same start-up in the BDF2 scheme's fluid steps (ChannelFlowParams::bdf2, paper/method/
  // 08_bdf2.md), its first step a Lie step whose stages it takes (start_bdf2). Its time error is
  // below the 5-point Laplacian's error against the series at these Δt, so the claim is on the
  // successive differences of the velocity (max over the nodes): order 2 (1.7 … 2.3 from each pair).
  const double t_end = 2e-5;
  std::vector<VelocityField> u;
  for (double dt : {4e-7, 2e-7, 1e-7, 0.5e-7}) {
    ChannelFlowParams p = narrow_channel(0.25e-6, dt);
    p.incremental_pressure = true;
    ChannelFlow lie(p);
    lie.keep_stages();
    lie.step();
    p.bdf2 = true;
    ChannelFlow flow(p);
    flow.start_bdf2(lie);
    for (long n = 1, steps = std::lround(t_end / dt); n < steps; ++n) flow.step();
    u.push_back(flow.velocity());
  }
  auto change = [&](int k) {
    double d = 0;
    for (std::size_t i = 0; i < u[k].u1.size(); ++i)
      d = std::max({d, std::abs(u[k].u1[i] - u[k + 1].u1[i]), std::abs(u[k].u2[i] - u[k + 1].u2[i])});
    return d;
  };
  const double d0 = change(0), d1 = change(1), d2 = change(2);
  std::printf("BDF2 start-up: successive changes %.3e %.3e %.3e m/s (dt = 4 -> 2 -> 1 -> 0.5e-7 s); orders %.2f %.2f\n", d0, d1, d2,
              std::log2(d0 / d1), std::log2(d1 / d2));
  EXPECT_NEAR(std::log2(d0 / d1), 2.0, 0.3);
  EXPECT_NEAR(std::log2(d1 / d2), 2.0, 0.3);
}

// The fastest speed left in the flow at t = T by a force that a pressure balances exactly (f =
// M⁻¹ Bᵀ q, the discrete gradient of a Gaussian q of 1000 Pa and width 0.5 um centred at x2 = y0
// in the narrow channel, H = 10 um, h = 0.125 um), after the Lie steps 1, 3, 4 from rest without
// body force. The exact answer is no flow at all.
double balanced_force_leak(double y0, double dt, bool incremental, double T = 30e-6) {
  ChannelFlowParams p = narrow_channel(0.125e-6, dt);
  p.body_force = 0;
  p.incremental_pressure = incremental;
  ChannelFlow flow(p);
  const ChannelMesh& m = flow.mesh();
  std::vector<double> q(m.pressure_nodes());
  for (int J = 0; J < m.pny(); ++J)
    for (int I = 0; I < m.pnx(); ++I) {
      const double dx = 2 * I * m.h - 10e-6, dy = 2 * J * m.h - y0;
      q[m.p(I, J)] = 1000.0 * std::exp(-(dx * dx + dy * dy) / (0.5e-6 * 0.5e-6));
    }
  VelocityField f(m);
  flow.projection().pressure_force(q, f);
  for (long n = 0; n < std::lround(T / dt); ++n) flow.step([&] { return &f; });
  flow.project();
  return max_speed(flow.velocity());
}

// The study's form (step 4 without a pressure) lets a force that a pressure balances drive a
// flow, most next to a wall and more the larger Δt: step 4's Helmholtz solve and step 1's
// gradient do not commute there. A membrane's tension is such a force (the pressure jump across
// it balances most of it), so cells near a wall feel a flow that is not there; this is the
// 100-cell layer's Δt error (experiments/cell_free_layer/README.md, Deviations). The
// incremental form carries the pressure into step 4, and the flow dies out. Measured (the
// Stokes scale of this force, max|f| w²/μ, is 0.36 m/s): the study's form leaves
// 3.45e-2 m/s with the bump 1 um off the wall at Δt = 3 us, 6.45e-3 at mid-channel, 4.66e-3 1 um
// off the wall at 5e-8 s; at 0.75 us, after 150 us, 2.40e-2 against the incremental form's 2.8e-5.
TEST(PressureSplitting, TheStudysFormLeaksABalancedForceMostNextToAWall) {
  const double wall = balanced_force_leak(1e-6, 3e-6, false);
  EXPECT_GT(wall, 4 * balanced_force_leak(5e-6, 3e-6, false));  // 5.3 times the mid-channel leak
  EXPECT_GT(wall, 5 * balanced_force_leak(1e-6, 5e-8, false));  // 7.4 times the leak at 5e-8 s
  EXPECT_LT(balanced_force_leak(1e-6, 7.5e-7, true, 150e-6), 1e-2 * balanced_force_leak(1e-6, 7.5e-7, false, 150e-6));  // 1/860
}

TEST(CouetteFlow, MovingWallsGiveTheLinearProfile) {
  ChannelFlowParams p = narrow_channel(0.5e-6, 2e-7);
  p.body_force = 0.0;
  p.wall_velocity[0] = -0.02;
  p.wall_velocity[1] = 0.05;
  ChannelFlow flow(p);
  while (flow.time() < 3e-4) flow.step();
  EXPECT_LT(max_profile_error(flow, [&](double y) { return -0.02 + 0.07 * y / p.height; }), 1e-10 * 0.05);
}

// A smooth field with divergence, zero on the walls (the projections' test input).
void set_divergent_field(ChannelFlow& flow) {
  const ChannelMesh& m = flow.mesh();
  const ChannelFlowParams& p = flow.params();
  for (int j = 1; j < m.ny; ++j)
    for (int i = 0; i < m.nx; ++i) {
      const double x = m.x(i) / p.length, y = m.y(j) / p.height;
      flow.velocity().u1[m.v(i, j)] = 0.1 * std::sin(2 * kPi * x) * std::sin(kPi * y) + 0.05 * y * y;
      flow.velocity().u2[m.v(i, j)] = 0.07 * std::cos(4 * kPi * x) * std::sin(2 * kPi * y) * x;
    }
}

double divergence_norm(const ChannelFlow& flow, const VelocityField& u) {  // ‖B u‖
  std::vector<double> div;
  flow.projection().divergence(u, div);
  return Eigen::Map<Eigen::VectorXd>(div.data(), Eigen::Index(div.size())).norm();
}

TEST(QuasiStokes, DiscreteDivergenceAfterProjectionIsBelowTheCgTolerance) {
  // B u^{n+1/3} = −(Δt/ρ) r, so ‖B u^{n+1/3}‖ ≤ tol ‖B uⁿ‖ whichever preconditioner is used.
  for (auto pc : {PressurePreconditioner::schur, PressurePreconditioner::laplacian}) {
    ChannelFlowParams p = narrow_channel(0.5e-6, 1e-7);
    p.preconditioner = pc;
    p.cg_tolerance = 1e-9;
    ChannelFlow flow(p);
    set_divergent_field(flow);
    const double before = divergence_norm(flow, flow.velocity());
    const ProjectionReport rep = flow.project();
    const double after = divergence_norm(flow, flow.velocity());
    EXPECT_LE(after, 1.0001 * p.cg_tolerance * before) << "preconditioner " << int(pc);
    EXPECT_LT(rep.iterations, pc == PressurePreconditioner::schur ? 4 : 100);
  }
}

TEST(CouplingProducts, TheResponseIsStep4sAndLeavesZerosForTheNextProduct) {
  // The GMRES products spread into force_rhs() and call response(), which clears the right-hand
  // sides as its solve reads them, so that the next product adds into zeros with no pass of its
  // own. In double precision the response must be add_force_response's to the bit, with or
  // without step 4's other solves in between (they have their own arrays); the hand-out is zeros
  // every time.
  ChannelFlowParams p = narrow_channel(0.25e-6, 1e-7);
  ChannelFlow flow(p);
  set_divergent_field(flow);
  ImplicitDiffusion& d = flow.diffusion();
  const ChannelMesh& m = flow.mesh();
  CouplingProducts products(m, d, flow.projection(), p.fluid.density, p.dt, CouplingProducts::Precision::kDouble);
  const std::size_t n = std::size_t(m.nx) * (m.ny - 1);
  const VelocityField force = flow.velocity();  // any field: here the divergent one, as N/m³
  auto all_zero = [n](std::pair<double*, double*> f) {
    for (std::size_t k = 0; k < n; ++k)
      if (f.first[k] != 0.0 || f.second[k] != 0.0) return false;
    return true;
  };
  auto fill = [&](std::pair<double*, double*> f) {
    for (std::size_t k = 0; k < n; ++k) {
      f.first[k] += m.h * m.h * force.u1[m.nx + k];
      f.second[k] += m.h * m.h * force.u2[m.nx + k];
    }
  };
  VelocityField expected(m), response(m);
  d.add_force_response(expected, force);
  for (int round = 0; round < 3; ++round) {
    const auto rhs = products.force_rhs();
    EXPECT_TRUE(all_zero(rhs)) << "round " << round;
    fill(rhs);
    products.response(response);
    EXPECT_EQ(response.u1, expected.u1) << "round " << round;
    EXPECT_EQ(response.u2, expected.u2) << "round " << round;
    if (round == 0) {  // step 4's own solves between two products
      const double body[2] = {p.body_force, 0.0};
      VelocityField u = flow.velocity();
      d.diffuse(u, body, &force);
    } else if (round == 1) {
      VelocityField u(m);
      d.add_force_response(u, force);
    }
  }
}

TEST(QuasiStokes, TheExactProjectionIsTheProjectionWithoutItsResidualCheck) {
  // The exact form (the semi-implicit coupling's GMRES products) inverts S once with the fast
  // solver and skips CG's check; S⁻¹ is exact up to round-off, so its result must be the CG
  // projection's (tolerance 1e-12 here) to round-off: divergence ≤ 1e-10 of the field's, and the
  // two fields equal to 1e-10 of the largest velocity (round-off of a 51k-unknown solve is
  // ≈ 1e-13; 1e-10 leaves room for the condition number of S, not for a wrong operator).
  ChannelFlowParams p = narrow_channel(0.25e-6, 1e-7);
  p.cg_tolerance = 1e-12;
  ChannelFlow flow(p);
  set_divergent_field(flow);
  VelocityField exact = flow.velocity();
  const double before = divergence_norm(flow, exact);
  std::vector<double> exact_pressure;
  flow.projection().project(flow.velocity(), exact, exact_pressure, p.fluid.density, p.dt, ProjectionForm::exact);
  flow.project();
  const double after = divergence_norm(flow, exact);
  EXPECT_LE(after, 1e-10 * before);
  double umax = 0, diff = 0;
  for (std::size_t k = 0; k < exact.u1.size(); ++k) {
    umax = std::max({umax, std::abs(exact.u1[k]), std::abs(exact.u2[k])});
    diff = std::max({diff, std::abs(exact.u1[k] - flow.velocity().u1[k]), std::abs(exact.u2[k] - flow.velocity().u2[k])});
  }
  EXPECT_LE(diff, 1e-10 * umax) << "largest difference " << diff << " m/s of " << umax;
  std::printf("exact projection: divergence %.3g of the field's, largest difference %.3g of the largest velocity\n",
              after / before, diff / umax);
}

TEST(QuasiStokes, TheProjectionAtOneNodeIsTheSweepsValue) {
  // projected_at (P u at the semi-implicit coupling's stencil nodes only) from the exact form's
  // pressure: the sweep's expressions at one node, so project's values to round-off at every node,
  // walls and the periodic seam included, on two threads too (the sweep splits its rows). Not the
  // same bits: the sweep rounds each triangle's sum as it stores it, where the node's own
  // expressions may fuse a product into the next sum (measured: 1.1e-15 of the largest velocity;
  // bound 1e-14, a wrong stencil entry is O(1)).
  ChannelFlowParams p = narrow_channel(0.25e-6, 1e-7);
  ChannelFlow flow(p);
  set_divergent_field(flow);
  const ChannelMesh& m = flow.mesh();
  const int threads_before = omp_get_max_threads();
  for (int threads : {1, 2}) {
    omp_set_num_threads(threads);
    VelocityField swept(m);
    std::vector<double> pressure;
    flow.projection().project(flow.velocity(), swept, pressure, p.fluid.density, p.dt, ProjectionForm::exact);
    double largest = 0, umax = 0;
    for (int j = 0; j <= m.ny; ++j)
      for (int i = 0; i < m.nx; ++i) {
        double v1, v2;
        flow.projection().projected_at(flow.velocity(), pressure, p.fluid.density, p.dt, i, j, v1, v2);
        largest = std::max({largest, std::abs(v1 - swept.u1[m.v(i, j)]), std::abs(v2 - swept.u2[m.v(i, j)])});
        umax = std::max({umax, std::abs(swept.u1[m.v(i, j)]), std::abs(swept.u2[m.v(i, j)])});
      }
    EXPECT_LE(largest, 1e-14 * umax) << threads << " threads";
    std::printf("P u at one node against the sweep (%d threads): largest difference %.2g of the largest velocity\n", threads,
                largest / umax);
  }
  omp_set_num_threads(threads_before);
}

TEST(WaveLikeAdvection, SmoothFieldTranslatesWithSecondOrderAccuracy) {
  // Constant V = (c, 0) translates u exactly: u(x, t) = u0(x − c t). The Taylor start step is a
  // Lax–Wendroff step, second order in τ and h, so with τ ∝ h the error should fall like h².
  const double c = 1.0, t_end = 0.25;
  auto u0 = [](double x, double y) { return std::sin(2 * kPi * x) * std::pow(std::sin(kPi * y), 2); };
  std::vector<double> err;
  for (int n : {32, 64, 128}) {
    const ChannelMesh m = ChannelMesh::make(1.0, 1.0, 1.0 / n);
    VelocityField V(m), u(m);
    for (int j = 0; j <= m.ny; ++j)
      for (int i = 0; i < m.nx; ++i) {
        V.u1[m.v(i, j)] = c;
        u.u1[m.v(i, j)] = u0(m.x(i), m.y(j));
        u.u2[m.v(i, j)] = -u0(m.x(i) + 0.3, m.y(j));
      }
    WaveLikeAdvection adv(m);
    const int steps = n;  // τ c / h = 0.25
    for (int s = 0; s < steps; ++s) adv.advect(V, u, t_end / steps, 1);
    double e = 0;
    for (int j = 0; j <= m.ny; ++j)
      for (int i = 0; i < m.nx; ++i) {
        e = std::max(e, std::abs(u.u1[m.v(i, j)] - u0(m.x(i) - c * t_end, m.y(j))));
        e = std::max(e, std::abs(u.u2[m.v(i, j)] + u0(m.x(i) + 0.3 - c * t_end, m.y(j))));
      }
    err.push_back(e);
  }
  EXPECT_GT(std::log2(err[0] / err[1]), 1.8);
  EXPECT_GT(std::log2(err[1] / err[2]), 1.8);
}

TEST(WaveLikeAdvection, SubstepsAgreeWithASingleStep) {
  // Q centred substeps of τ = Δt/Q approximate the same translation: the difference between
  // Q = 1 and Q = 4 is of the scheme's order, (c Δt / L)² = 6e-5 here.
  const ChannelMesh m = ChannelMesh::make(1.0, 1.0, 1.0 / 64);
  VelocityField V(m), a(m);
  for (int j = 0; j <= m.ny; ++j)
    for (int i = 0; i < m.nx; ++i) {
      V.u1[m.v(i, j)] = 1.0;
      a.u1[m.v(i, j)] = std::sin(2 * kPi * m.x(i)) * std::pow(std::sin(kPi * m.y(j)), 2);
    }
  VelocityField b = a;
  WaveLikeAdvection adv(m);
  for (int s = 0; s < 32; ++s) { adv.advect(V, a, 1.0 / 128, 1); adv.advect(V, b, 1.0 / 128, 4); }
  double d = 0;
  for (std::size_t k = 0; k < a.u1.size(); ++k) d = std::max(d, std::abs(a.u1[k] - b.u1[k]));
  EXPECT_LT(d, 1e-3);
}

TEST(WaveLikeAdvection, TheGatherKernelKeepsItsStatedArithmetic) {
  // detail::gather_row (fluid/detail/advection_kernels.hpp) against its formula written out here
  // node by node: with AVX2, the vector body against the scalar node expression the kernel states
  // (its sums in order, its fused multiply-adds; bit for bit through the wrapping first node, the
  // vector body and the remainder: row lengths 2 to 13 and 160). Without AVX2 the kernel is that
  // plain loop, and the comparison only guards the row's indexing.
  std::mt19937 gen(11);
  std::uniform_real_distribution<double> value(-1.0, 1.0);
  int differing = 0, compared = 0;
  for (int nx : {2, 3, 4, 5, 6, 7, 8, 9, 12, 13, 160}) {
    auto random = [&](std::size_t n) {
      std::vector<double> v(n);
      for (double& x : v) x = value(gen);
      return v;
    };
    const std::vector<double> glj = random(nx), guj = random(nx), gld = random(nx), gud = random(nx);
    const std::vector<double> vlx = random(2 * nx), vly = random(2 * nx), vux = random(2 * nx), vuy = random(2 * nx);
    const double inv_h = 1.0 / 0.3125e-6;
    const std::size_t o = nx, od = 0;  // node row 1 over triangle rows 1 and 0
    std::vector<double> A(nx), C(nx);
    detail::gather_row(nx, inv_h, o, od, glj.data(), guj.data(), gld.data(), gud.data(), vlx.data(), vly.data(), vux.data(),
                       vuy.data(), A.data(), C.data());
    for (int i = 0; i < nx; ++i) {
      const int im = i == 0 ? nx - 1 : i - 1;
      const std::size_t a = o + i, b = o + im, cc = od + i, d = od + im;
#if defined(__AVX2__) && defined(__FMA__)
      double sum = std::fma(glj[i], -vlx[a] - vly[a], glj[im] * vlx[b]);
      sum = std::fma(gld[i], vly[cc], sum);
      sum = std::fma(-guj[im], vuy[b], sum);
      sum = std::fma(gud[im], vux[d] + vuy[d], sum);
      sum = std::fma(-gud[i], vux[cc], sum);
#else
      const double sum = glj[i] * (-vlx[a] - vly[a]) + glj[im] * vlx[b] + gld[i] * vly[cc] - guj[im] * vuy[b] +
                         gud[im] * (vux[d] + vuy[d]) - gud[i] * vux[cc];
#endif
      const double expected_a = 0.5 * sum * inv_h;
      const double expected_c = -(glj[i] + glj[im] + gld[i] + guj[im] + gud[im] + gud[i]) / 6.0;
      differing += (A[i] != expected_a) + (C[i] != expected_c);
      compared += 2;
    }
  }
  EXPECT_EQ(differing, 0) << "of " << compared << " values, the kernel's differ in bits from its stated arithmetic";
}

TEST(WaveLikeAdvection, AShiftAlongX1CommutesWithTheStepBitForBit) {
  // Every node's arithmetic is the same expression whichever column it is in (the wrapping
  // first column and the last triangle written out apart, the gather four nodes at a time in
  // AVX2 with the same operations one node at a time at the row's ends): so shifting V and u by
  // s columns and advecting gives the shifted result, bit for bit. 22 columns put the nodes of
  // every shift through the wrap, the vector body and the remainder in turn; a node whose
  // arithmetic depended on its path would differ in its last bits.
  const ChannelMesh m = ChannelMesh::make(22e-6, 8e-6, 1e-6);
  VelocityField V(m), u(m);
  std::uint32_t state = 12345;
  auto next = [&] { state = state * 1664525u + 1013904223u; return double(state >> 8) / double(1u << 24) - 0.5; };
  for (std::size_t k = 0; k < V.u1.size(); ++k) {
    V.u1[k] = 0.3 + 0.1 * next();
    V.u2[k] = 0.1 * next();
    u.u1[k] = next();
    u.u2[k] = next();
  }
  auto shifted = [&](const VelocityField& f, int s) {
    VelocityField g(m);
    for (int j = 0; j <= m.ny; ++j)
      for (int i = 0; i < m.nx; ++i) {
        g.u1[m.v(i + s, j)] = f.u1[m.v(i, j)];
        g.u2[m.v(i + s, j)] = f.u2[m.v(i, j)];
      }
    return g;
  };
  WaveLikeAdvection adv(m);
  VelocityField ref = u;
  adv.advect(V, ref, 6e-6, 2);  // τ |V| / h ≈ 0.9: τ² M⁻¹A as large as u, so that its last bits show
  for (int s : {1, 2, 3, 5}) {
    VelocityField a = shifted(u, s);
    adv.advect(shifted(V, s), a, 6e-6, 2);
    const VelocityField b = shifted(ref, s);
    EXPECT_TRUE(a.u1 == b.u1 && a.u2 == b.u2) << "shift by " << s << " columns";
  }
}

// A manufactured unsteady flow: stream function ψ = e^{−t} sin(kx) s(y), s = a (y(1−y))²,
// u = (ψ_y, −ψ_x), zero on both walls, divergence-free; p = 0; the force is
// f = ρ(∂u/∂t + u·∇u) − μΔu.
struct Manufactured {
  double rho = 1.0, mu = 0.05, a = 5.0, k = 2 * kPi;
  double s(double y) const { return a * std::pow(y * (1 - y), 2); }
  double s1(double y) const { return 2 * a * y * (1 - y) * (1 - 2 * y); }
  double s2(double y) const { return 2 * a * (1 - 6 * y + 6 * y * y); }
  double s3(double y) const { return 2 * a * (-6 + 12 * y); }
  void velocity(double x, double y, double t, double& u1, double& u2) const {
    const double E = std::exp(-t);
    u1 = E * std::sin(k * x) * s1(y);
    u2 = -E * k * std::cos(k * x) * s(y);
  }
  void force(double x, double y, double t, double& f1, double& f2) const {
    const double E = std::exp(-t), S = std::sin(k * x), C = std::cos(k * x);
    const double u1 = E * S * s1(y), u2 = -E * k * C * s(y);
    const double u1x = E * k * C * s1(y), u1y = E * S * s2(y);
    const double u2x = E * k * k * S * s(y), u2y = -E * k * C * s1(y);
    const double lap1 = E * S * (-k * k * s1(y) + s3(y));
    const double lap2 = -E * k * C * (-k * k * s(y) + s2(y));
    f1 = rho * (-u1 + u1 * u1x + u2 * u1y) - mu * lap1;
    f2 = rho * (-u2 + u1 * u2x + u2 * u2y) - mu * lap2;
  }
};

TEST(ManufacturedSolution, VelocityConvergesSecondOrderInHWithDtProportionalToHSquared) {
  // Expected: P1-iso-P2 velocity is O(h²) at the nodes; Lie splitting and backward Euler are
  // O(Δt) = O(h²) with Δt ∝ h²; so the max nodal error at fixed t should fall like h².
  const Manufactured ms;
  const double t_end = 0.2;
  std::vector<double> err;
  for (int n : {16, 32, 64}) {
    ChannelFlowParams p;
    p.fluid = {ms.rho, ms.mu};
    p.length = p.height = 1.0;
    p.mesh_size = 1.0 / n;
    const int steps = 20 * (n / 16) * (n / 16);
    p.dt = t_end / steps;
    p.body_force = 0.0;
    ChannelFlow flow(p);
    const ChannelMesh& m = flow.mesh();
    for (int j = 0; j <= m.ny; ++j)
      for (int i = 0; i < m.nx; ++i) ms.velocity(m.x(i), m.y(j), 0.0, flow.velocity().u1[m.v(i, j)], flow.velocity().u2[m.v(i, j)]);
    VelocityField f(m);
    for (int s = 0; s < steps; ++s)
      flow.step([&] {  // the force of step 4, at t^{n+1}
        const double t1 = flow.time() + p.dt;
        for (int j = 0; j <= m.ny; ++j)
          for (int i = 0; i < m.nx; ++i) ms.force(m.x(i), m.y(j), t1, f.u1[m.v(i, j)], f.u2[m.v(i, j)]);
        return &f;
      });
    double e = 0;
    for (int j = 0; j <= m.ny; ++j)
      for (int i = 0; i < m.nx; ++i) {
        double u1, u2;
        ms.velocity(m.x(i), m.y(j), flow.time(), u1, u2);
        e = std::max({e, std::abs(flow.velocity().u1[m.v(i, j)] - u1), std::abs(flow.velocity().u2[m.v(i, j)] - u2)});
      }
    err.push_back(e);
  }
  const double o1 = std::log2(err[0] / err[1]), o2 = std::log2(err[1] / err[2]);
  std::printf("manufactured: errors %.3e %.3e %.3e, observed orders %.2f %.2f\n", err[0], err[1], err[2], o1, o2);
  EXPECT_GT(o2, 1.7);
  EXPECT_LT(o2, 2.5);
}

}  // namespace
}  // namespace rbc


namespace rbc {
namespace {

TEST(Determinism, TwoDimensionalFlowIsBitIdenticalWithOneAndTwoThreads) {
  // Every OpenMP loop is element-wise (no parallel reductions), and FFTW plans are made with
  // FFTW_ESTIMATE, so the thread count must not change a single bit.
  auto run = [](int threads) {
    omp_set_num_threads(threads);
    ChannelFlowParams p = narrow_channel(0.5e-6, 1e-7);
    ChannelFlow flow(p);
    const ChannelMesh& m = flow.mesh();
    for (int j = 1; j < m.ny; ++j)
      for (int i = 0; i < m.nx; ++i) flow.velocity().u2[m.v(i, j)] = 0.01 * std::sin(2 * kPi * i / m.nx) * std::sin(kPi * j / m.ny);
    for (int n = 0; n < 30; ++n) flow.step();
    return flow.velocity();
  };
  const int saved = omp_get_max_threads();
  const VelocityField a = run(1), b = run(2);
  omp_set_num_threads(saved);
  EXPECT_EQ(a.u1, b.u1);
  EXPECT_EQ(a.u2, b.u2);
}

}  // namespace
}  // namespace rbc
