// The semi-implicit coupling (paper/method/04_semi_implicit_coupling.md): the membrane stiffness,
// the mobility of step 4, and the coupling itself against the study's explicit scheme. Each test
// names the property it checks.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <functional>
#include <numbers>
#include <random>

#include <omp.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include "diagnostics/cell_diagnostics.hpp"
#include "fluid/channel_flow.hpp"
#include "io/checkpoint.hpp"
#include "semi_implicit/detail/bf16_lu_solve.hpp"
#include "immersed_boundary/immersed_boundary.hpp"
#include "semi_implicit/detail/phase_average_kernel.hpp"
#include "semi_implicit/step_mobility.hpp"
#include "membrane/membrane_stiffness.hpp"
#include "scene/simulation.hpp"

namespace rbc {
namespace {

Points polygon(int n, double radius, double stretch_x = 1.0) {
  Points r;
  for (int i = 0; i < n; ++i) {
    const double t = 2 * std::numbers::pi * i / n;
    r.push_back({radius * stretch_x * std::cos(t), radius * std::sin(t)});
  }
  return r;
}

// Central differences of the force: column j of −∂F/∂r.
Eigen::MatrixXd finite_difference_hessian(const MembraneModel& m, const Points& r, double s_e, double eps) {
  const int n = int(r.size());
  Eigen::MatrixXd H(2 * n, 2 * n);
  for (int j = 0; j < 2 * n; ++j) {
    Points rp = r, rm = r, Fp, Fm;
    rp[j / 2][j % 2] += eps;
    rm[j / 2][j % 2] -= eps;
    membrane_energy(m, rp, s_e, &Fp);
    membrane_energy(m, rm, s_e, &Fm);
    for (int i = 0; i < 2 * n; ++i) H(i, j) = -(Fp[i / 2][i % 2] - Fm[i / 2][i % 2]) / (2 * eps);
  }
  return H;
}

TEST(MembraneStiffness, IsTheExactHessianForStretchedSpringsAndTheAreaAtItsTarget) {
  // Stretching alone, every spring stretched (a polygon 3 % larger than the rest circle): the
  // kept part is the whole Hessian. Area penalty alone at s = s_e: Gauss–Newton is exact.
  MembraneModel m = MembraneModel::from(MembraneConstants{}, 24, 2.8e-6);
  const Points r = polygon(24, 1.03 * 2.8e-6);
  const double eps = 1e-11;
  MembraneModel stretch = m;
  stretch.kb = 0;
  stretch.area_penalty = false;
  const Eigen::MatrixXd Ks = membrane_stiffness(stretch, r, 1.0).dense(), Hs = finite_difference_hessian(stretch, r, 1.0, eps);
  EXPECT_LT((Ks - Hs).norm(), 1e-6 * Hs.norm());
  MembraneModel area = m;
  area.kl = area.kb = 0;
  const double s_e = enclosed_area(r);
  const Eigen::MatrixXd Ka = membrane_stiffness(area, r, s_e).dense(), Ha = finite_difference_hessian(area, r, s_e, eps);
  EXPECT_LT((Ka - Ha).norm(), 1e-6 * Ha.norm());
}

TEST(MembraneStiffness, IsSymmetricPositiveSemiDefiniteAndCloseToTheHessianOnACompressedEllipse) {
  // The full model on a compressed, elongated 76-gon: the dropped parts (compressed springs'
  // transverse term, k_b t ∇²t, the area's curvature term) are small, and what is kept is ⪰ 0.
  const MembraneModel m = MembraneModel::from(MembraneConstants{}, 76, 2.8e-6);
  const Points r = polygon(76, 0.97 * 2.8e-6, 1.2);
  const double s_e = 0.9 * enclosed_area(r);
  const Eigen::MatrixXd K = membrane_stiffness(m, r, s_e).dense(), H = finite_difference_hessian(m, r, s_e, 1e-11);
  EXPECT_LT((K - K.transpose()).norm(), 1e-14 * K.norm());
  const Eigen::VectorXd ev = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(K).eigenvalues();
  EXPECT_GT(ev.minCoeff(), -1e-12 * ev.maxCoeff());
  const double rel = (K - H).norm() / H.norm();
  std::printf("|K - H| / |H| = %.3e on a compressed ellipse\n", rel);
  EXPECT_LT(rel, 0.1);
}

// The StepMobility tests' channel: 10 × 5 µm, h = 0.25 µm, Δt = 1e-6 s, with its step mobility.
struct SmallChannel {
  static ChannelFlowParams params() {
    ChannelFlowParams p;
    p.length = 10e-6;
    p.height = 5e-6;
    p.mesh_size = 0.25e-6;
    p.dt = 1e-6;
    return p;
  }
  ChannelFlowParams p = params();
  ChannelFlow flow{p};
  StepMobility mobility{flow.mesh(), flow.diffusion(), flow.projection(), p.fluid.density, p.dt};
};

TEST(StepMobility, EqualsSpreadSolveProjectInterpolate) {
  // M F from the table against the long way (S, a fast solve of step 4, P, J),
  // for nodes near both walls, across the periodic boundary and in the bulk.
  SmallChannel ch;
  ChannelFlow& flow = ch.flow;
  const ChannelFlowParams& p = ch.p;
  const ChannelMesh& mesh = flow.mesh();
  StepMobility& mobility = ch.mobility;
  const Points r = {{0.1e-6, 2.5e-6}, {9.95e-6, 0.3e-6}, {5.03e-6, 4.9e-6}, {3.3e-6, 2.2e-6}, {-0.7e-6, 1.0e-6}, {3.5e-6, 2.3e-6}};
  std::mt19937 gen(3);
  std::uniform_real_distribution<double> d(-1, 1);
  Points F;
  for (std::size_t k = 0; k < r.size(); ++k) F.push_back({d(gen), d(gen)});
  // The long way: f = S F (N/m³); P; w = A⁻¹ h² f per component; P; U = J w.
  VelocityField f(mesh), w(mesh);
  spread_forces(mesh, r, F, f);
  std::vector<double> pressure(mesh.pressure_nodes(), 0.0);
  flow.diffusion().add_force_response(w, f);
  flow.projection().project(w, w, pressure, p.fluid.density, p.dt, ProjectionForm::iterative);
  Points U;
  interpolate_velocity(mesh, w, r, U);
  Eigen::MatrixXd M;
  mobility.matrix(r, M);
  const Eigen::VectorXd MF = M * Eigen::Map<const Eigen::VectorXd>(F[0].data(), 2 * F.size());
  double err = 0, scale = 0;
  for (std::size_t k = 0; k < r.size(); ++k) {
    err = std::max(err, (MF.segment<2>(2 * k) - U[k]).norm());
    scale = std::max(scale, U[k].norm());
  }
  std::printf("max |M F - J P A^-1 S F| = %.2e of max |U| = %.2e; |M - M^T| / |M| = %.3f\n", err, scale,
              (M - M.transpose()).norm() / M.norm());
  EXPECT_LT(err, 1e-9 * scale);  // the projection's CG tolerance is 1e-10
}

TEST(StepMobility, TabulatesASourceRowWhenFirstNeededWithTheValuesOfTheWholeTable) {
  // matrix() tabulates only the source rows under its nodes' stencils; a table built row by row,
  // in whatever order the nodes ask, gives M bit for bit as one with every row tabulated first.
  SmallChannel lazy, whole;
  const int rows = lazy.flow.mesh().ny - 1;
  EXPECT_EQ(lazy.mobility.rows_tabulated(), 0);
  const Points low = {{1.1e-6, 0.6e-6}, {2.0e-6, 0.7e-6}}, high = {{9.9e-6, 4.1e-6}, {-0.3e-6, 4.4e-6}};
  Eigen::MatrixXd M_low, M_high, M_whole;
  lazy.mobility.matrix(low, M_low);
  // Stencils of nodes at y = 0.6 and 0.7 µm (h = 0.25 µm) reach interior rows 0–3.
  EXPECT_EQ(lazy.mobility.rows_tabulated(), 4);
  EXPECT_EQ(lazy.mobility.table_bytes(), std::size_t(4) * 8 * lazy.flow.mesh().nx * rows * sizeof(double));
  lazy.mobility.matrix(high, M_high);
  EXPECT_LT(lazy.mobility.rows_tabulated(), rows);
  whole.mobility.prepare_phase_average(1e-6);  // tabulates every source row
  EXPECT_EQ(whole.mobility.rows_tabulated(), rows);
  whole.mobility.matrix(high, M_whole);
  EXPECT_TRUE(M_high == M_whole);
  whole.mobility.matrix(low, M_whole);
  EXPECT_TRUE(M_low == M_whole);
}

TEST(StepMobility, PeskinAutocorrelationSumsToOneWithNoFirstMoment) {
  // From Σ_j φ(r − j) = 1 and Σ_j (r − j) φ(r − j) = 0: Σ_d c(d − z) = 1 and Σ_d (d − z) c(d − z)
  // = 0 for every z; c is even and vanishes from |z| = 4 on.
  for (double z : {0.0, 0.13, 0.5, 0.77, 1.0, 2.31, 3.9}) {
    double sum = 0, moment = 0;
    for (int d = -8; d <= 8; ++d) {
      sum += peskin_autocorrelation(d - z);
      moment += (d - z) * peskin_autocorrelation(d - z);
    }
    EXPECT_NEAR(sum, 1.0, 1e-13) << "z = " << z;     // round-off of 17 quadratures: measured 2.2e-16
    EXPECT_NEAR(moment, 0.0, 1e-13) << "z = " << z;  // measured 1.3e-16
    EXPECT_DOUBLE_EQ(peskin_autocorrelation(z), peskin_autocorrelation(-z));
  }
  EXPECT_EQ(peskin_autocorrelation(4.0), 0.0);
  EXPECT_GT(peskin_autocorrelation(3.9), 0.0);
}

TEST(StepMobility, PhaseAveragedMatrixIsTheMeanOverShiftsAlongTheFlow) {
  // M̄ against the mean of M over 64 equal shifts of all nodes along x1 across two mesh cells
  // (the integrand is periodic in the shift, so that mean converges fast), for a cell near a
  // wall and across the periodic boundary; and M̄ does not change when the nodes move along x1.
  SmallChannel ch;
  const ChannelFlowParams& p = ch.p;
  StepMobility& mobility = ch.mobility;
  Points r = polygon(24, 1.5e-6, 1.3);
  for (auto& x : r) x += Eigen::Vector2d(0.3e-6, 1.7e-6);  // 0.2 µm from the wall, across x1 = 0
  mobility.prepare_phase_average(3.0e-6);
  Eigen::MatrixXd averaged, shifted, M, mean = Eigen::MatrixXd::Zero(48, 48);
  mobility.phase_averaged_matrix(r, averaged);
  const int shifts = 64;
  for (int s = 0; s < shifts; ++s) {
    Points rs = r;
    for (auto& x : rs) x.x() += 2 * p.mesh_size * s / shifts;
    mobility.matrix(rs, M);
    mean += M / shifts;
  }
  const double err = (averaged - mean).norm() / mean.norm();
  Points moved = r;
  for (auto& x : moved) x.x() += 0.37 * p.mesh_size;
  mobility.phase_averaged_matrix(moved, shifted);
  const double moved_err = (shifted - averaged).norm() / averaged.norm();
  mobility.matrix(r, M);
  std::printf("|M_avg - mean of M over shifts| / |M| = %.2e; after a move along x1 %.2e; |M - M_avg| / |M| = %.3f\n", err,
              moved_err, (M - averaged).norm() / averaged.norm());
  EXPECT_LT(err, 1e-3);         // measured 5.8e-4: H interpolated in z at h/4, in single precision (1.5e-4 at h/8)
  EXPECT_LT(moved_err, 1e-12);  // M̄ depends on x1 only through differences (measured 2e-16)
}

}  // namespace
}  // namespace rbc

namespace rbc {
namespace {

// A channel of the study (L × H, mesh h, cell-free Re0) without cells.
Scene channel(double length, double height, double h, double reynolds0) {
  Scene s;
  s.source = "test";
  s.length = length;
  s.height = height;
  s.mesh_size = h;
  s.reynolds0 = reynolds0;
  return s;
}

// n steps, each checked.
void advance(Simulation& sim, long n) {
  for (long k = 0; k < n; ++k) {
    sim.step();
    sim.check_health();
  }
}

// The second-order tests' scene: the narrow channel, one s* = 0.55 cell from (5, 3) µm released in
// the developed flow (a smooth start: from rest, the body force meets the no-slip walls at once),
// the incremental form of the pressure; and its cell's centroid after T = 0.1 ms at Δt.
Scene second_order_scene(const std::string& coupling, const std::string& scheme) {
  Scene s = channel(20e-6, 10e-6, 0.25e-6, 0.5556);
  s.cells.push_back({{5e-6, 3e-6}, 0.55, 0.0});
  s.coupling = coupling;
  s.projection = "incremental";
  s.scheme = scheme;
  s.end = 1e-4;
  return s;
}

Eigen::Vector2d centroid_at_end(Scene s, double dt) {
  s.dt = dt;
  Simulation sim(s);
  sim.start_from_cell_free_profile();
  advance(sim, std::lround(s.end / dt));
  return area_centroid(sim.cells()[0].nodes);
}

// The observed orders from the centroids at Δt, 2Δt, 4Δt (whole, x1, x2), printed with them.
Eigen::Vector3d observed_orders(const Eigen::Vector2d& e1, const Eigen::Vector2d& e2, const Eigen::Vector2d& e4) {
  const Eigen::Vector3d o(std::log2((e4 - e2).norm() / (e2 - e1).norm()), std::log2(std::abs(e4.x() - e2.x()) / std::abs(e2.x() - e1.x())),
                          std::log2(std::abs(e4.y() - e2.y()) / std::abs(e2.y() - e1.y())));
  std::printf("centroid at 0.1 ms (um): (%.6f, %.6f) (%.6f, %.6f) (%.6f, %.6f) at dt, 2 dt, 4 dt; observed order %.2f (x1 %.2f, x2 %.2f)\n",
              e1.x() * 1e6, e1.y() * 1e6, e2.x() * 1e6, e2.y() * 1e6, e4.x() * 1e6, e4.y() * 1e6, o[0], o[1], o[2]);
  return o;
}

// Runs a scene to t_end; returns the cells.
std::vector<Cell> run_to(Scene s, const std::string& coupling, double dt, double t_end, int substeps = 1) {
  s.coupling = coupling;
  s.dt = dt;
  s.advection_substeps = substeps;
  s.end = t_end;
  Simulation sim(s);
  advance(sim, std::lround(t_end / dt));
  return sim.cells();
}

// Largest distance between corresponding nodes once the centroids are put on top of each other,
// m: the shape difference.
double shape_distance(const Points& a, const Points& b) {
  const Eigen::Vector2d d = area_centroid(a) - area_centroid(b);
  double m = 0;
  for (std::size_t i = 0; i < a.size(); ++i) m = std::max(m, (a[i] - b[i] - d).norm());
  return m;
}

TEST(StepMobility, ThePhaseAveragedPairKernelKeepsItsStatedArithmeticBitForBit) {
  // The kernel's comment fixes its arithmetic (so that the preconditioner blocks, and with them
  // every multi-cell run, do not change with the compiler's schedule): here it is written out
  // operation by operation, each rounding explicit, and the kernel must give the same bits.
  std::mt19937 gen(7);
  std::uniform_real_distribution<double> weight(-0.1, 0.7), frac(0.0, 1.0);
  std::uniform_real_distribution<float> table(-1e-3f, 1e-3f);
  int differing = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    float h0[16], h1[16];
    for (int i = 0; i < 16; ++i) { h0[i] = table(gen); h1[i] = table(gen); }
    const double wk = weight(gen), f = frac(gen);
    const double wl[4] = {weight(gen), weight(gen), weight(gen), weight(gen)};
    double a[4] = {weight(gen), weight(gen), weight(gen), weight(gen)};
    double expected[4];
    for (int v = 0; v < 4; ++v) {
      volatile float sum = 0.0f;  // volatile: every operation rounded where written
      for (int q = 0; q < 4; ++q) {
        const volatile double wkf = wk * f;
        const volatile float b1 = float(wkf * wl[q]);
        const volatile double wkw = wk * wl[q];
        const volatile float b0 = float(wkw) - b1;
        const volatile float product = b1 * h1[4 * q + v];
#ifdef __FMA__
        const volatile float t = std::fma(float(b0), h0[4 * q + v], float(product));
#else  // the kernel's stated arithmetic without fused multiply-adds: both products rounded
        const volatile float first = b0 * h0[4 * q + v];
        const volatile float t = first + product;
#endif
        sum = sum + t;
      }
      const volatile double widened = double(sum);
      expected[v] = a[v] + widened;
    }
    detail::add_interpolated_pair(h0, h1, wk, f, wl, a);
    for (int v = 0; v < 4; ++v) differing += a[v] != expected[v];
  }
  EXPECT_EQ(differing, 0) << "of 8000 values, the kernel's differ in bits from its stated arithmetic";
}

TEST(SemiImplicit, ThePreconditionersSweepKeepsItsStatedArithmeticBitForBit) {
  // bf16_lu_solve.hpp fixes the sweep's arithmetic: each update one fused multiply-add, the
  // updates of a row in column order (forward) and reverse column order (back). Here it is written
  // out column by column, each rounding explicit, on the factors by columns; the sweep, reading
  // its own packing of them (AVX2: panels of eight columns), must give the same bits. Sizes below,
  // at and above multiples of the panel, 152 being a 76-node cell.
  std::mt19937 gen(11);
  std::normal_distribution<float> entry(0.0f, 0.3f), value(0.0f, 1.0f);
  std::uniform_real_distribution<float> diagonal(0.5f, 2.0f);
  int differing = 0, values = 0;
  for (int m : {1, 2, 7, 8, 9, 15, 16, 17, 24, 31, 77, 152, 153}) {
    for (int trial = 0; trial < 4; ++trial) {
      std::vector<float> lu(std::size_t(m) * m);  // by columns; what bfloat16 keeps of it
      for (float& e : lu) e = detail::from_bf16(detail::to_bf16(entry(gen)));
      std::vector<float> inverse_diagonal(m), x(m);
      for (float& d : inverse_diagonal) d = 1.0f / diagonal(gen);
      for (float& v : x) v = value(gen);
      std::vector<float> expected = x;
      volatile float* e = expected.data();  // every operation rounded where written
      auto update = [&](int i, int j) {       // e_i − LU_ij e_j, one rounding (two without FMA)
#ifdef __FMA__
        e[i] = std::fma(-lu[std::size_t(j) * m + i], float(e[j]), float(e[i]));
#else
        const volatile float product = lu[std::size_t(j) * m + i] * e[j];
        e[i] = e[i] - product;
#endif
      };
      for (int j = 0; j < m; ++j)
        for (int i = j + 1; i < m; ++i) update(i, j);
      for (int j = m - 1; j >= 0; --j) {
        e[j] = e[j] * inverse_diagonal[j];
        for (int i = 0; i < j; ++i) update(i, j);
      }
      std::vector<std::uint16_t> packed;
      detail::pack_lu_bf16(lu.data(), m, packed);
      ASSERT_GE(packed.size(), std::size_t(m) * (m - 1)) << "m = " << m;  // every entry off the diagonal
      detail::lu_solve_bf16(packed.data(), inverse_diagonal.data(), m, x.data());
      for (int i = 0; i < m; ++i) {
        differing += std::memcmp(&x[i], &expected[i], sizeof(float)) != 0;
        ++values;
      }
    }
  }
  EXPECT_EQ(differing, 0) << "of " << values << " values, the sweep's differ in bits from its stated arithmetic";
}

TEST(SemiImplicitValidationExperiment, NarrowChannelSingleCellConvergesToTheExplicitScheme) {
  // The study's narrow channel on h = 0.25 µm (our explicit limit there is ≈ 7e-8 s), one
  // s* = 0.55 cell from (5, 3) µm, to t = 0.25 ms. Reference: the explicit scheme at Δt = 2e-8 s.
  // The semi-implicit scheme at Δt = 1, 2, 4 × 1e-7 s (up to 6 times the explicit limit; the
  // 20-fold target is checked on the wide channel by bench_channel and the stability map).
  // Claims, stated before the run: (a) its Δt error is first order — successive differences
  // halve with Δt, ratio 2 (accepted 1.5 … 2.7, order 0.6 … 1.4); (b) the first-order
  // (Richardson) extrapolation of the semi-implicit heights agrees with the explicit reference
  // within the reference's own first-order error, slope · 2e-8 s, doubled for the O(Δt²) rest;
  // (c) shapes: the centroid-aligned node distance to the explicit shape at 1e-7 s is below
  // 1 % of R0 and shrinks with Δt.
  Scene s = channel(20e-6, 10e-6, 0.25e-6, 0.5556);
  s.cells.push_back({{5e-6, 3e-6}, 0.55, 0.0});
  const double T = 2.5e-4;
  const std::vector<Cell> ex = run_to(s, "explicit", 2e-8, T);
  const std::vector<Cell> s1 = run_to(s, "semi-implicit", 1e-7, T), s2 = run_to(s, "semi-implicit", 2e-7, T),
                          s4 = run_to(s, "semi-implicit", 4e-7, T);
  auto y = [](const std::vector<Cell>& c) { return area_centroid(c[0].nodes).y(); };
  const double d12 = y(s2) - y(s1), d24 = y(s4) - y(s2);
  const double slope = d12 / 1e-7;  // dy/dΔt, m/s
  const double extrapolated = y(s1) - slope * 1e-7;
  const double tol = 2 * std::abs(slope) * 2e-8;
  const double sh1 = shape_distance(s1[0].nodes, ex[0].nodes), sh2 = shape_distance(s2[0].nodes, ex[0].nodes);
  std::printf("y(0.25 ms): explicit %.5f um; semi-implicit %.5f %.5f %.5f um (dt = 1, 2, 4e-7 s)\n", y(ex) * 1e6, y(s1) * 1e6,
              y(s2) * 1e6, y(s4) * 1e6);
  std::printf("difference ratio %.3f; extrapolated %.5f um vs explicit, |diff| %.2e um (tolerance %.2e um)\n", d24 / d12,
              extrapolated * 1e6, std::abs(extrapolated - y(ex)) * 1e6, tol * 1e6);
  std::printf("shape distance to explicit: %.4f um (1e-7 s), %.4f um (2e-7 s)\n", sh1 * 1e6, sh2 * 1e6);
  EXPECT_GT(y(ex) - 3e-6, 0.4e-6);  // the cell migrates (measured 0.565 um)
  EXPECT_GT(d24 / d12, 1.5);
  EXPECT_LT(d24 / d12, 2.7);
  EXPECT_LT(std::abs(extrapolated - y(ex)), tol);
  EXPECT_LT(sh1, 0.01 * 2.8e-6);
  EXPECT_LT(sh1, sh2);
}

TEST(SemiImplicitValidationExperiment, TheExtrapolatedLieSchemeIsSecondOrderInDt) {
  // second_order_scene by the semi-implicit coupling at Δt = 1, 2, 4 × 1e-7 s in the extrapolated
  // Lie scheme ([time] scheme = "lie-extrapolated": 2 L_{Δt/2}² − L_Δt each step). Claim: its
  // successive centroid differences shrink by 4 per halving (observed order 1.6 … 2.6), in x1 (the
  // cell's travel) and in the distance as a whole. Measured when written: 1.85 and 1.85. In the
  // study's form of the pressure the same runs give 1.39 (x1 0.82):
  // paper/method/07_second_order_in_time.md.
  const Scene s = second_order_scene("semi-implicit", "lie-extrapolated");
  const Eigen::Vector3d o = observed_orders(centroid_at_end(s, 1e-7), centroid_at_end(s, 2e-7), centroid_at_end(s, 4e-7));
  EXPECT_GT(o[0], 1.6);
  EXPECT_LT(o[0], 2.6);
  EXPECT_GT(o[1], 1.6);
  EXPECT_LT(o[1], 2.6);
}

TEST(SemiImplicitValidationExperiment, TheBdf2SchemeIsSecondOrderInDt) {
  // The same in the BDF2 scheme ([time] scheme = "bdf2", paper/method/08_bdf2.md): claim, observed
  // order 1.6 … 2.6 in the whole and in x1 (the claim of the test above). The orders from 2, 4,
  // 8e-7 s are printed second: chapter 8's variants read that run too.
  const Scene s = second_order_scene("semi-implicit", "bdf2");
  const Eigen::Vector2d e1 = centroid_at_end(s, 1e-7), e2 = centroid_at_end(s, 2e-7), e4 = centroid_at_end(s, 4e-7);
  const Eigen::Vector3d o = observed_orders(e1, e2, e4);
  observed_orders(e2, e4, centroid_at_end(s, 8e-7));
  EXPECT_GT(o[0], 1.6);
  EXPECT_LT(o[0], 2.6);
  EXPECT_GT(o[1], 1.6);
  EXPECT_LT(o[1], 2.6);
}

TEST(SemiImplicitValidationExperiment, TheBdf2SchemeWithTheExplicitCouplingReachesTheSameCentroid) {
  // second_order_scene in the BDF2 scheme with the study's explicit coupling (the force F(s_e)
  // alone, paper/method/08_bdf2.md) at 2.5e-8 s, against the semi-implicit coupling's BDF2 run at
  // 1e-7 s: claim, the centroids agree within 3e-4 um (the semi-implicit run's change from 2e-7 s,
  // 2.2e-4 um in the test above, bounds its own error at second order).
  const Eigen::Vector2d e = centroid_at_end(second_order_scene("explicit", "bdf2"), 2.5e-8);
  const Eigen::Vector2d si = centroid_at_end(second_order_scene("semi-implicit", "bdf2"), 1e-7);
  std::printf("centroid at 0.1 ms (um): explicit BDF2 (%.6f, %.6f), semi-implicit BDF2 (%.6f, %.6f); distance %.2e um\n", e.x() * 1e6,
              e.y() * 1e6, si.x() * 1e6, si.y() * 1e6, (e - si).norm() * 1e6);
  EXPECT_LT((e - si).norm(), 3e-10);
}

TEST(SemiImplicitValidationExperiment, WideChannelFourCellsConvergeToTheExplicitScheme) {
  // The study's four-cell set-up (its Sec. 3.1.2: s* = 1 at (25, 10), (25, 40), (65, 10), (65, 40) µm,
  // 100 × 50 µm, h = 0.3125 µm, Re0 = 2.778), 0.1 ms. Reference: explicit at 3e-8 s (9e-8 s,
  // stable with one s* = 0.55 cell, is not with these s* = 1 cells: measured). Semi-implicit at
  // 1e-6 and 2e-6 s (Q = 2). Claims, stated before the run: every centroid
  // coordinate's difference to the explicit one shrinks with Δt, and at 1e-6 s it is within
  // 2 % of that cell's displacement over the run plus 1 nm; shapes within 1 % of R0.
  // Measured (commit of this test): x differences 0.0156 and 0.0321 um of 1.458 um moved (first
  // order), shapes 0.0024 um. In 0.1 ms the cells drift only ≈ 1e-4 um across the flow, so the
  // x2 checks are within the 1 nm floor: this test validates the streamwise motion and the shapes;
  // the lateral migration is validated by the narrow-channel test above.
  Scene s = channel(100e-6, 50e-6, 0.3125e-6, 2.778);
  for (const auto& c : {Eigen::Vector2d(25e-6, 10e-6), Eigen::Vector2d(25e-6, 40e-6), Eigen::Vector2d(65e-6, 10e-6),
                        Eigen::Vector2d(65e-6, 40e-6)})
    s.cells.push_back({c, 1.0, 0.0});
  const double T = 1e-4;
  const std::vector<Cell> ex = run_to(s, "explicit", 3e-8, T, 1);
  const std::vector<Cell> s1 = run_to(s, "semi-implicit", 1e-6, T, 2), s2 = run_to(s, "semi-implicit", 2e-6, T, 2);
  for (int c = 0; c < 4; ++c) {
    const Eigen::Vector2d e = area_centroid(ex[c].nodes), a = area_centroid(s1[c].nodes), b = area_centroid(s2[c].nodes);
    const Eigen::Vector2d moved = e - s.cells[c].center;
    const double shape = shape_distance(s1[c].nodes, ex[c].nodes);
    std::printf("cell %d: moved (%.4f, %.4f) um; semi-implicit - explicit at 1e-6 s (%.2e, %.2e) um, at 2e-6 s (%.2e, %.2e) um; "
                "shape %.2e um\n", c, moved.x() * 1e6, moved.y() * 1e6, (a - e).x() * 1e6, (a - e).y() * 1e6, (b - e).x() * 1e6,
                (b - e).y() * 1e6, shape * 1e6);
    for (int k = 0; k < 2; ++k) {
      EXPECT_LE(std::abs((a - e)[k]), std::abs((b - e)[k]) + 1e-9) << "cell " << c << " coordinate " << k;
      EXPECT_LT(std::abs((a - e)[k]), 0.02 * std::abs(moved[k]) + 1e-9) << "cell " << c << " coordinate " << k;
    }
    EXPECT_LT(shape, 0.01 * 2.8e-6) << "cell " << c;
  }
}

// Three s* = 0.55 cells 5 um apart, long axis across the flow, in the narrow channel on mesh h;
// semi-implicit, n steps of dt.
Scene three_cells(double h, double dt, int n, int substeps) {
  Scene s = channel(20e-6, 10e-6, h, 0.5556);
  for (double x : {4e-6, 9e-6, 14e-6}) s.cells.push_back({{x, 4e-6}, 0.55, 1.5707963});
  s.coupling = "semi-implicit";
  s.dt = dt;
  s.advection_substeps = substeps;
  s.end = n * dt;
  return s;
}

TEST(SemiImplicit, GmresGoingOnWithFreshBlocksGivesTheSameSteps) {
  // When GMRES does not converge with the blocks as they are, the blocks are rebuilt at the
  // step's nodes and GMRES goes on from its last iterate; the velocity correction is then a
  // combination of the second run's products only. Forced here at every step (after 0 and 2
  // iterations) for three cells 5 um apart in the narrow channel, 150 steps of 1e-6 s, against
  // the same run left alone. Claim, stated before the run: both solve every step to the same
  // relative residual 1e-4, so the nodes agree to well under 1e-3 of their displacement (a
  // wrong combination, e.g. keeping the first run's products, changes the force by O(Δt K U) and
  // the cells by far more). Measured: 1.4–2.0e-5 um (after 0) and 0.9–1.6e-5 um (after 2) of
  // 4.0–4.5 um moved, ≈ 4e-6 of it; with the first run's products kept (mutation) the run stopped
  // at step 4 (CFL 4.1: the membrane coupling went unstable).
  const Scene s = three_cells(0.25e-6, 1e-6, 150, 2);
  auto run = [&](int fresh_after) {
    Simulation sim(s);
    if (fresh_after >= 0) sim.semi_implicit_step()->set_fresh_blocks_after(fresh_after);
    advance(sim, 150);
    const long fresh = sim.semi_implicit_step()->cost().fresh_rebuilds;
    if (fresh_after == 0) {
      EXPECT_EQ(fresh, 150);  // every step
    } else if (fresh_after > 0) {
      EXPECT_GT(fresh, 0);  // the steps that needed more than fresh_after iterations
    } else {
      EXPECT_EQ(fresh, 0);
    }
    return sim.cells();
  };
  const std::vector<Cell> plain = run(-1), fresh0 = run(0), fresh2 = run(2);
  for (int c = 0; c < 3; ++c) {
    const double moved = (area_centroid(plain[c].nodes) - s.cells[c].center).norm();
    double d0 = 0, d2 = 0;
    for (std::size_t i = 0; i < plain[c].nodes.size(); ++i) {
      d0 = std::max(d0, (fresh0[c].nodes[i] - plain[c].nodes[i]).norm());
      d2 = std::max(d2, (fresh2[c].nodes[i] - plain[c].nodes[i]).norm());
    }
    std::printf("cell %d: moved %.4f um; largest node difference %.2e um (fresh after 0), %.2e um (after 2)\n", c, moved * 1e6,
                d0 * 1e6, d2 * 1e6);
    EXPECT_LT(d0, 1e-3 * moved) << "cell " << c;
    EXPECT_LT(d2, 1e-3 * moved) << "cell " << c;
  }
}

TEST(SemiImplicit, ARunWhosePressureCgMissesItsToleranceStops) {
  // The study's Laplacian preconditioner iterates the pressure CG to its tolerance or to 200
  // iterations; a pressure short of the tolerance is not the step's, so the health check stops
  // the run and names the residual (before, the step used it silently). Two iterations are far
  // too few for the tolerance 1e-10 on this mesh: the CG must stop short of it within two steps.
  Scene s = three_cells(0.25e-6, 1e-6, 5, 2);
  s.pressure_preconditioner = "laplacian";
  s.cg_max_iterations = 2;
  Simulation sim(s);
  try {
    advance(sim, 5);
    ADD_FAILURE() << "the run went on with an unconverged pressure";
  } catch (const RunFailure& e) {
    EXPECT_NE(std::string(e.what()).find("pressure CG of step 1 stopped"), std::string::npos) << e.what();
    EXPECT_LE(sim.steps(), 2);  // the first step whose divergence is not at round-off (from rest: the second)
  }
  // Its usual iterations: the same scene runs.
  s.cg_max_iterations = 200;
  Simulation fine(s);
  EXPECT_NO_THROW(advance(fine, 5));
}

TEST(SemiImplicit, AThreadTeamSmallerThanAskedForSpreadsEveryCell) {
  // The runtime may give a parallel region fewer threads than omp_get_max_threads() (OMP_DYNAMIC,
  // OMP_THREAD_LIMIT, a nested region): here three threads are asked for inside an active region
  // of two (one runs the cells, the other waits) with nesting off, so every inner region gets a
  // team of one. The cells' run must then be the one-thread run, bit for bit (the work
  // divided among the team the runtime gave, not among the threads asked for: before, the cells
  // of the missing threads were never spread).
  // Two of the cells, 10 um apart, long axes along x1: wider than half a spreading slab, so the
  // products spread through the per-thread arrays.
  Scene s = three_cells(0.25e-6, 1e-6, 20, 2);
  s.cells.resize(2);
  s.cells[0].center = {5e-6, 4e-6};
  s.cells[1].center = {15e-6, 6e-6};
  for (auto& c : s.cells) c.angle = 0;
  const int max_threads = omp_get_max_threads(), levels = omp_get_max_active_levels();
  auto run = [&]() {
    Simulation sim(s);
    advance(sim, 20);
    return sim.cells();
  };
  omp_set_num_threads(1);
  const std::vector<Cell> one = run();
  omp_set_num_threads(3);
  omp_set_max_active_levels(1);
  std::vector<Cell> limited;
  std::string failure;
  int outer = 0;
#pragma omp parallel num_threads(2)
  {
    if (omp_get_thread_num() == 0) {
      outer = omp_get_num_threads();
      try {
        limited = run();
      } catch (const std::exception& e) {  // (an exception may not leave the region)
        failure = e.what();
      }
    }
  }
  EXPECT_EQ(failure, "");
  omp_set_max_active_levels(levels);
  omp_set_num_threads(max_threads);
  if (outer < 2) GTEST_SKIP() << "the runtime gave the outer region one thread: no smaller team to test";
  ASSERT_EQ(limited.size(), one.size());
  for (std::size_t c = 0; c < one.size(); ++c)
    for (std::size_t i = 0; i < one[c].nodes.size(); ++i) ASSERT_EQ(limited[c].nodes[i], one[c].nodes[i]) << "cell " << c << " node " << i;
}

// Three cells 5 um apart in the narrow channel, 150 steps of 1e-6 s, solved once with the
// library's CouplingOptions and once with one option changed; both keep the system and its 1e-4
// relative residual. Claim, stated before the runs (as for the fresh blocks above): the nodes
// agree to well under 1e-3 of their displacement; and they are not the same bits (the option
// reaches the solver: with it ignored, the last expectation fails).
void expect_the_same_steps_to_the_solvers_tolerance(const std::function<void(CouplingOptions&)>& option, const char* what) {
  const Scene s = three_cells(0.25e-6, 1e-6, 150, 2);
  CouplingOptions changed;
  option(changed);
  auto run = [&](const CouplingOptions& options) {
    Simulation sim(s, options);
    advance(sim, 150);
    return sim.cells();
  };
  const std::vector<Cell> plain = run(CouplingOptions{}), other = run(changed);
  bool same_bits = true;
  for (int c = 0; c < 3; ++c) {
    const double moved = (area_centroid(plain[c].nodes) - s.cells[c].center).norm();
    double d = 0;
    for (std::size_t i = 0; i < plain[c].nodes.size(); ++i) {
      d = std::max(d, (other[c].nodes[i] - plain[c].nodes[i]).norm());
      same_bits = same_bits && other[c].nodes[i] == plain[c].nodes[i];
    }
    std::printf("cell %d: moved %.4f um; largest node difference, %s, %.2e um\n", c, moved * 1e6, what, d * 1e6);
    EXPECT_LT(d, 1e-3 * moved) << "cell " << c;
  }
  EXPECT_FALSE(same_bits);
}

TEST(SemiImplicit, TheLinearStartTakesTheSameStepsToTheSolversTolerance) {
  // GMRES started from the straight line through the last two steps' solutions instead of the last one.
  expect_the_same_steps_to_the_solvers_tolerance([](CouplingOptions& o) { o.start = CouplingOptions::Start::kLinear; },
                                                 "linear against constant start");
}

TEST(SemiImplicit, FixedBlocksTakeTheSameStepsToTheSolversTolerance) {
  // Each cell's preconditioner block applied as built instead of turned with the cell. GMRES's
  // products stay exact, so only the path changes.
  expect_the_same_steps_to_the_solvers_tolerance([](CouplingOptions& o) { o.turn_blocks = false; }, "fixed against turned blocks");
}

TEST(SemiImplicit, DoubleProductSolvesTakeTheSameStepsToTheSolversTolerance) {
  // The products' step-4 and pressure solves in double instead of single precision (relative error
  // ≈ 1e-7, FastSolvers.TheSinglePrecisionSolverIsTheDoubleOneToFloatRoundOff, against GMRES's 1e-4).
  expect_the_same_steps_to_the_solvers_tolerance(
      [](CouplingOptions& o) { o.product_precision = CouplingProducts::Precision::kDouble; }, "double against single solves");
}

TEST(SemiImplicit, PAtTheStencilsTakesTheSameStepsToTheSolversTolerance) {
  // J P made from P at the stencils' nodes only (QuasiStokesProjection::projected_at) instead of
  // over the mesh (the default's choice for three cells in the narrow channel): the same values
  // to round-off (QuasiStokes.TheProjectionAtOneNodeIsTheSweepsValue), so the same steps to the
  // solver's tolerance, as in expect_the_same_steps_to_the_solvers_tolerance. The bits may be the
  // same (where the compiler fuses no product into a sum: the Debug build), so the option is seen
  // reaching the solver by the step's own flag instead.
  const Scene s = three_cells(0.25e-6, 1e-6, 150, 2);
  auto run = [&](CouplingOptions::Projection where, bool& at_footprint) {
    CouplingOptions o;
    o.projection = where;
    Simulation sim(s, o);
    advance(sim, 150);
    at_footprint = sim.semi_implicit_step()->last_projection_at_footprint();
    return sim.cells();
  };
  bool plain_at_footprint = true, other_at_footprint = false;
  const std::vector<Cell> plain = run(CouplingOptions::Projection::kCheaper, plain_at_footprint),
                          other = run(CouplingOptions::Projection::kFootprint, other_at_footprint);
  EXPECT_FALSE(plain_at_footprint) << "three cells in the narrow channel: the footprint is not under an eighth of the mesh";
  EXPECT_TRUE(other_at_footprint);
  for (int c = 0; c < 3; ++c) {
    const double moved = (area_centroid(plain[c].nodes) - s.cells[c].center).norm();
    double d = 0;
    for (std::size_t i = 0; i < plain[c].nodes.size(); ++i) d = std::max(d, (other[c].nodes[i] - plain[c].nodes[i]).norm());
    std::printf("cell %d: moved %.4f um; largest node difference, P at the stencils against over the mesh, %.2e um\n", c, moved * 1e6,
                d * 1e6);
    EXPECT_LT(d, 1e-3 * moved) << "cell " << c;
  }
}

TEST(SemiImplicit, OneCellsCorrectionInSinglePrecisionTakesTheDoubleSteps) {
  // One cell's correction A⁻¹ S (−Δt K U) by the products' single-precision solve against the
  // double one: one cell in the narrow channel, 300 steps of 2e-6 s. Claim, stated before the run:
  // the solve's relative error (a few 1e-7) stays a few 1e-7 of the correction, so the nodes agree
  // to under 1e-5 of their displacement; and the option reaches the solve (not the same bits).
  Scene s = channel(20e-6, 10e-6, 0.25e-6, 0.5556);
  s.cells.push_back({{10e-6, 3e-6}, 0.7, 0.0});
  s.coupling = "semi-implicit";
  s.dt = 2e-6;
  s.end = 300 * s.dt;
  auto run = [&](CouplingProducts::Precision precision) {
    CouplingOptions o;
    o.product_precision = precision;
    Simulation sim(s, o);
    advance(sim, 300);
    return sim.cells()[0].nodes;
  };
  const Points single = run(CouplingProducts::Precision::kSingleWherePossible), twice = run(CouplingProducts::Precision::kDouble);
  const double moved = (area_centroid(single) - s.cells[0].center).norm();
  double d = 0;
  bool same_bits = true;
  for (std::size_t i = 0; i < single.size(); ++i) {
    d = std::max(d, (single[i] - twice[i]).norm());
    same_bits = same_bits && single[i] == twice[i];
  }
  std::printf("one cell moved %.4f um; largest node difference, single against double correction, %.2e um\n", moved * 1e6, d * 1e6);
  EXPECT_LT(d, 1e-5 * moved);
  EXPECT_FALSE(same_bits);
}

TEST(SemiImplicit, ProductSolvesStayDoubleWhereStep4HasNoSinglePrecisionForm) {
  // An obstacle makes step 4 a constrained solve, the Laplacian preconditioner makes the
  // projection iterate: there the products use the fluid's own double solves, whatever is asked.
  const ChannelMesh m = ChannelMesh::make(10e-6, 5e-6, 0.25e-6);
  auto single = [&](bool obstacle, PressurePreconditioner pc) {
    ImplicitDiffusion d(m, 1000.0, 1.2e-3, 1e-6);
    QuasiStokesProjection p(m, pc, 1e-10, 200);
    std::unique_ptr<ObstacleConstraint> c;
    if (obstacle) {
      c = std::make_unique<ObstacleConstraint>(ObstacleGeometry(m, {Obstacle{{2e-6, 4e-6}, {0.0, 1e-6}, "bottom"}}), d.helmholtz(), 1e-10,
                                               UzawaPreconditioner::capacitance);
      d.set_constraint(c.get());
    }
    return CouplingProducts(m, d, p, 1000.0, 1e-6, CouplingProducts::Precision::kSingleWherePossible).single_precision();
  };
  EXPECT_TRUE(single(false, PressurePreconditioner::schur));
  EXPECT_FALSE(single(true, PressurePreconditioner::schur));
  EXPECT_FALSE(single(false, PressurePreconditioner::laplacian));
}

TEST(SemiImplicit, TurnedBlocksRestOnTheStiffnessTurningWithTheCell) {
  // What turned blocks rely on (semi_implicit_coupling.hpp): a cell turned rigidly by R and moved
  // has K(R r + t) = R K(r) Rᵀ node by node (the springs' energies do not change), and
  // best_fit_rotation finds R from the two sets of nodes, also across the periodic image (t = L e1).
  const MembraneModel m = MembraneModel::from(MembraneConstants{}, 76, 2.8e-6);
  const Points r = polygon(76, 0.97 * 2.8e-6, 1.2);
  const double s_e = 0.9 * enclosed_area(r), theta = 0.7;
  const Eigen::Matrix2d R = Eigen::Rotation2Dd(theta).toRotationMatrix();
  Points turned = r;
  for (auto& p : turned) p = R * p + Eigen::Vector2d(100e-6 + 0.3e-6, 2e-6);
  const Eigen::MatrixXd K = membrane_stiffness(m, r, s_e).dense(), Kt = membrane_stiffness(m, turned, s_e).dense();
  Eigen::MatrixXd RKRt = K;
  for (int i = 0; i < 76; ++i)
    for (int j = 0; j < 76; ++j) RKRt.block<2, 2>(2 * i, 2 * j) = R * K.block<2, 2>(2 * i, 2 * j) * R.transpose();
  EXPECT_LT((Kt - RKRt).norm(), 1e-10 * K.norm());
  EXPECT_LT((best_fit_rotation(r, turned) - R).norm(), 1e-12);
  // Nodes moved along as well as turned (tank-treading, deformation): the rotation of the best
  // fit, not of any one node; a cell that has not turned, the identity.
  Points noisy = turned;
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-0.05e-6, 0.05e-6);
  for (auto& p : noisy) p += Eigen::Vector2d(u(rng), u(rng));
  EXPECT_LT(std::abs(Eigen::Rotation2Dd(best_fit_rotation(r, noisy)).angle() - theta), 0.02);
  EXPECT_LT((best_fit_rotation(r, r) - Eigen::Matrix2d::Identity()).norm(), 1e-15);
}

TEST(SemiImplicit, TurnedBlocksNeedFewerProductsWhileTheCellsTurn) {
  // Three cells across the flow in the narrow channel turn by about a radian as they are carried
  // over 300 steps of 1e-6 s. Their blocks are built once and kept (no rebuild on the interval nor
  // after many iterations; fresh ones only if GMRES fails 60 iterations). Claim: applied turned,
  // they need fewer GMRES products over the run than fixed. Measured: 7882 against 8507 (fixed
  // blocks failed 60 iterations twice and were built afresh); with R and Rᵀ swapped in the
  // preconditioner 8858, and the test fails. (A first version let the rebuilds
  // run as in the scenes and compared products; turned blocks then took 36 rebuilds against 45
  // and 2464 products against 2401, and with R and Rᵀ swapped 60 rebuilds and 2066 products: the
  // rebuilds trade against the products, so the blocks are held here.)
  // The claim holds with GMRES's linear start (below); with the constant start these three cells
  // take 9159 products turned against 8864 fixed (measured): where turned blocks pay is the
  // crowd's developed flow (paper/method/04_semi_implicit_coupling.md), not every small case.
  Scene s = three_cells(0.25e-6, 1e-6, 300, 2);
  auto run = [&](const std::string& blocks) {
    CouplingOptions options;
    options.start = CouplingOptions::Start::kLinear;
    options.turn_blocks = blocks == "turned";
    Simulation sim(s, options);
    sim.semi_implicit_step()->set_block_refresh_steps(100000);
    sim.semi_implicit_step()->set_rebuild_above_iterations(100000);
    sim.semi_implicit_step()->set_fresh_blocks_after(60);
    const std::vector<Cell> start = sim.cells();
    advance(sim, 300);
    const auto& cost = sim.semi_implicit_step()->cost();
    std::printf("%s blocks: %ld products, %ld blocks built; the cells turned by", blocks.c_str(), cost.product_count, cost.block_builds);
    for (std::size_t c = 0; c < start.size(); ++c)
      std::printf(" %.3f", Eigen::Rotation2Dd(best_fit_rotation(start[c].nodes, sim.cells()[c].nodes)).angle());
    std::printf(" rad\n");
    return std::pair<long, long>(cost.product_count, cost.block_builds);
  };
  const auto fixed = run("fixed"), turned = run("turned");
  EXPECT_LT(turned.first, fixed.first);
}

TEST(SemiImplicit, ARunResumedWhileTheBlocksAreRebuiltSoonerTakesTheSameSteps) {
  // The rebuild interval, shortened after steps with fresh blocks and grown back later, is state:
  // a run saved and resumed in the middle of that must take the same steps bit for bit. Forced
  // here by fresh blocks after 1 iteration (three cells, coarse narrow channel, 40 steps of
  // 5e-7 s, saved after step 17). Checked by mutation: with the interval not restored on load,
  // the nodes differ.
  for (const char* blocks : {"fixed", "turned"}) {  // turned blocks: their rotations come from the saved nodes
    const Scene s = three_cells(0.5e-6, 5e-7, 40, 1);
    CouplingOptions options;
    options.turn_blocks = std::string(blocks) == "turned";
    Simulation straight(s, options);
    straight.semi_implicit_step()->set_fresh_blocks_after(1);
    advance(straight, 40);
    const std::string path = (std::filesystem::temp_directory_path() / "rbcflow_fresh_blocks_checkpoint.bin").string();
    long fresh_before = 0;
    {
      Simulation first(s, options);
      first.semi_implicit_step()->set_fresh_blocks_after(1);
      advance(first, 17);
      fresh_before = first.semi_implicit_step()->cost().fresh_rebuilds;
      CheckpointWriter w;
      first.save(w);
      w.commit(path);
    }
    Simulation resumed(s, options);
    resumed.semi_implicit_step()->set_fresh_blocks_after(1);
    CheckpointReader r(path);
    resumed.load(r);
    advance(resumed, 23);
    EXPECT_GT(fresh_before, 0);
    EXPECT_GT(resumed.semi_implicit_step()->cost().fresh_rebuilds, 0);
    for (std::size_t c = 0; c < s.cells.size(); ++c)
      for (std::size_t i = 0; i < straight.cells()[c].nodes.size(); ++i)
        ASSERT_EQ(resumed.cells()[c].nodes[i], straight.cells()[c].nodes[i]) << blocks << " blocks, cell " << c << " node " << i;
  }
}

}  // namespace
}  // namespace rbc
