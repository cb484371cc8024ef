// The fast solvers (FFT in x1, banded in x2) against a direct sparse LU (Eigen) on small grids.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include <Eigen/SparseLU>
#include <omp.h>

#include "fast_solvers/periodic_banded_solver.hpp"
#include "semi_implicit/coupling_products.hpp"
#include "fem/divergence_stencil.hpp"
#include "fem/p1_operators.hpp"
#include "fluid/diffusion.hpp"
#include "fluid/quasi_stokes.hpp"

namespace rbc {
namespace {

std::vector<double> random_vector(std::size_t n, unsigned seed) {
  std::mt19937 gen(seed);
  std::uniform_real_distribution<double> d(-1.0, 1.0);
  std::vector<double> v(n);
  for (double& x : v) x = d(gen);
  return v;
}

// max |A x − b| for x = the solver's A⁻¹ b.
double largest_residual(PeriodicBandedSolver& solver, const PeriodicBandedSolver::Operator& apply, const std::vector<double>& b) {
  std::vector<double> x(b.size()), r(b.size());
  solver.solve(b.data(), x.data());
  apply(x, r);
  double e = 0;
  for (std::size_t k = 0; k < b.size(); ++k) e = std::max(e, std::abs(r[k] - b[k]));
  return e;
}

// S p = B M⁻¹ Bᵀ p, M = h² (QuasiStokesProjection's apply_schur, by the same operations).
PeriodicBandedSolver::Operator schur_complement(const ChannelMesh& m, const DivergenceStencil& B) {
  return [&m, &B](const std::vector<double>& p, std::vector<double>& out) {
    std::vector<double> g1, g2;
    B.apply_transpose(p, g1, g2);
    for (std::size_t n = 0; n < g1.size(); ++n) { g1[n] *= 1.0 / (m.h * m.h); g2[n] *= 1.0 / (m.h * m.h); }
    B.apply(g1, g2, out);
  };
}

TEST(FastSolvers, HelmholtzSolveMatchesSparseLU) {
  // The step-4 operator (ρh²/Δt + 4μ) I − μ (5-point neighbours), assembled here independently
  // as a sparse matrix over the interior rows, Dirichlet walls.
  const ChannelMesh m = ChannelMesh::make(12e-6, 8e-6, 0.5e-6);
  const double rho = 1000, mu = 1.2e-3, dt = 1e-7;
  const int nx = m.nx, rows = m.ny - 1;
  const double diag = rho * m.h * m.h / dt + 4 * mu;
  std::vector<Eigen::Triplet<double>> t;
  for (int r = 0; r < rows; ++r)
    for (int i = 0; i < nx; ++i) {
      const int n = r * nx + i;
      t.emplace_back(n, n, diag);
      t.emplace_back(n, r * nx + (i + 1) % nx, -mu);
      t.emplace_back(n, r * nx + (i + nx - 1) % nx, -mu);
      if (r > 0) t.emplace_back(n, n - nx, -mu);
      if (r + 1 < rows) t.emplace_back(n, n + nx, -mu);
    }
  Eigen::SparseMatrix<double> A(nx * rows, nx * rows);
  A.setFromTriplets(t.begin(), t.end());
  Eigen::SparseLU<Eigen::SparseMatrix<double>> lu(A);
  // Our solver: one diffusion step with u^{n+2/3} = b (ρh²/Δt)⁻¹, zero walls and no force.
  const std::vector<double> b = random_vector(std::size_t(nx) * rows, 1);
  VelocityField u(m);
  for (int r = 0; r < rows; ++r)
    for (int i = 0; i < nx; ++i) u.u1[m.v(i, r + 1)] = b[r * nx + i] / (rho * m.h * m.h / dt);
  ImplicitDiffusion diffusion(m, rho, mu, dt);
  const double zero[2] = {0, 0};
  diffusion.diffuse(u, zero, nullptr);
  const Eigen::VectorXd x = lu.solve(Eigen::Map<const Eigen::VectorXd>(b.data(), Eigen::Index(b.size())));
  double e = 0, s = 0;
  for (int r = 0; r < rows; ++r)
    for (int i = 0; i < nx; ++i) {
      e = std::max(e, std::abs(u.u1[m.v(i, r + 1)] - x[r * nx + i]));
      s = std::max(s, std::abs(x[r * nx + i]));
    }
  EXPECT_LT(e, 1e-12 * s);
}

TEST(FastSolvers, ThePairSolveGivesEachFieldBitForBitAsTheSingleSolve) {
  // solve_pair shares the factors' reads between two fields (one thread) or gives a thread each
  // field whole (two threads); each result must be the one solve() gives on one thread and on two
  // (same plans, same operations per value), on a grid large enough to use the threads, for an
  // operator symmetric in x1 (step 4's: the real path) and one that is not (the complex path).
  const ChannelMesh m = ChannelMesh::make(100e-6, 50e-6, 0.3125e-6);
  const int nx = m.nx, rows = m.ny - 1;
  const double diag = 1000 * m.h * m.h / 1e-6 + 4 * 1.2e-3;
  for (const double skew : {0.0, 0.3e-3}) {
    auto apply = [=](const std::vector<double>& in, std::vector<double>& out) {
      for (int r = 0; r < rows; ++r)
        for (int i = 0; i < nx; ++i) {
          double s = diag * in[r * nx + i] - (1.2e-3 + skew) * in[r * nx + (i + 1) % nx] - (1.2e-3 - skew) * in[r * nx + (i + nx - 1) % nx];
          if (r > 0) s -= 1.2e-3 * in[(r - 1) * nx + i];
          if (r + 1 < rows) s -= 1.2e-3 * in[(r + 1) * nx + i];
          out[r * nx + i] = s;
        }
    };
    PeriodicBandedSolver solver(nx, rows, apply, false);
    EXPECT_EQ(solver.real_symbol(), skew == 0.0);
    const std::vector<double> b1 = random_vector(std::size_t(nx) * rows, 2), b2 = random_vector(std::size_t(nx) * rows, 3);
    const int threads = omp_get_max_threads();
    std::vector<double> x1(b1.size()), x2(b1.size());
    omp_set_num_threads(1);
    solver.solve(b1.data(), x1.data());
    solver.solve(b2.data(), x2.data());
    EXPECT_NE(x1, x2);
    for (int t : {1, 2}) {
      omp_set_num_threads(t);
      std::vector<double> p1 = b1, p2 = b2, q1(b1.size()), q2(b1.size()), y1(b1.size());
      solver.solve_pair(p1.data(), p2.data(), p1.data(), p2.data());  // in place, as the diffusion step calls it
      solver.solve_pair(b1.data(), b2.data(), q1.data(), q2.data());  // out of place
      solver.solve(b1.data(), y1.data());
      EXPECT_EQ(p1, x1) << t << " threads, skew " << skew;
      EXPECT_EQ(p2, x2) << t << " threads, skew " << skew;
      EXPECT_EQ(q1, x1) << t << " threads, skew " << skew;
      EXPECT_EQ(q2, x2) << t << " threads, skew " << skew;
      EXPECT_EQ(y1, x1) << t << " threads, skew " << skew;
      // The clearing pair (the GMRES products' call): the same bits, into an output aligned as the
      // solver's own arrays (the inverse transform writes it directly) and one that is not (through
      // the solver's array), and both right-hand sides left zero.
      for (const std::size_t shift : {std::size_t(0), std::size_t(1)}) {
        std::vector<double> c1 = b1, c2 = b2, o1(b1.size() + 1), o2(b1.size() + 1);
        solver.solve_pair_clearing(c1.data(), c2.data(), o1.data() + shift, o2.data() + shift);
        EXPECT_TRUE(std::equal(x1.begin(), x1.end(), o1.begin() + shift)) << t << " threads, skew " << skew << ", shift " << shift;
        EXPECT_TRUE(std::equal(x2.begin(), x2.end(), o2.begin() + shift)) << t << " threads, skew " << skew << ", shift " << shift;
        EXPECT_EQ(c1, std::vector<double>(b1.size(), 0.0)) << t << " threads, skew " << skew;
        EXPECT_EQ(c2, std::vector<double>(b1.size(), 0.0)) << t << " threads, skew " << skew;
      }
    }
    omp_set_num_threads(threads);
  }
}

TEST(FastSolvers, TheSinglePrecisionSolverIsTheDoubleOneToFloatRoundOff) {
  // The GMRES products' solves in single precision (coupling_products.hpp): step 4's pair on the wide grid and the
  // Schur complement's single solve on its coarse grid (a constant kernel: compared mean-free).
  // Claim: every value within 1e-6 of the field's largest (float's 6e-8, times the growth of
  // round-off through a transform of 320 and a substitution over 159 rows), on one and two
  // threads; and the right-hand sides cleared as by the double solver.
  const ChannelMesh m = ChannelMesh::make(100e-6, 50e-6, 0.3125e-6);
  const int nx = m.nx, rows = m.ny - 1;
  const double diag = 1000 * m.h * m.h / 3e-6 + 4 * 1.2e-3;
  auto apply = [=](const std::vector<double>& in, std::vector<double>& out) {
    for (int r = 0; r < rows; ++r)
      for (int i = 0; i < nx; ++i) {
        double s = diag * in[r * nx + i] - 1.2e-3 * (in[r * nx + (i + 1) % nx] + in[r * nx + (i + nx - 1) % nx]);
        if (r > 0) s -= 1.2e-3 * in[(r - 1) * nx + i];
        if (r + 1 < rows) s -= 1.2e-3 * in[(r + 1) * nx + i];
        out[r * nx + i] = s;
      }
  };
  auto largest_difference = [](const std::vector<double>& a, const std::vector<double>& b) {
    double d = 0, s = 0;
    for (std::size_t k = 0; k < a.size(); ++k) { d = std::max(d, std::abs(a[k] - b[k])); s = std::max(s, std::abs(a[k])); }
    return d / s;
  };
  PeriodicBandedSolver exact(nx, rows, apply, false);
  SinglePeriodicBandedSolver single(nx, rows, apply, false);
  const std::vector<double> b1 = random_vector(std::size_t(nx) * rows, 5), b2 = random_vector(std::size_t(nx) * rows, 6);
  std::vector<double> x1(b1.size()), x2(b1.size());
  exact.solve_pair(b1.data(), b2.data(), x1.data(), x2.data());
  const int threads = omp_get_max_threads();
  for (int t : {1, 2}) {
    omp_set_num_threads(t);
    std::vector<double> c1 = b1, c2 = b2, y1(b1.size()), y2(b1.size());
    single.solve_pair_clearing(c1.data(), c2.data(), y1.data(), y2.data());
    const double e1 = largest_difference(x1, y1), e2 = largest_difference(x2, y2);
    std::printf("step 4, %d threads: single against double %.2e, %.2e of the largest value\n", t, e1, e2);
    EXPECT_LT(e1, 1e-6);
    EXPECT_LT(e2, 1e-6);
    EXPECT_GT(e1, 0.0);  // it is single precision
    EXPECT_EQ(c1, std::vector<double>(b1.size(), 0.0));
    EXPECT_EQ(c2, std::vector<double>(b1.size(), 0.0));
  }
  omp_set_num_threads(threads);
  // The products' projection (CouplingProducts::project), whose Schur complement solve is the other
  // single-precision one. What the products use is the projected velocity. (A first claim, on
  // the pressure values, within 1e-6 of the largest, failed at 1.6e-6: S is a Laplacian on T_2h,
  // its x1-constant mode conditioned ≈ (2 · 81/π)² ≈ 2.7e3, so its solve loses more of float's
  // digits than step 4's Helmholtz, whose symbol is close to its diagonal; but the smooth modes
  // that carry the error have small gradients.) Claim: the projected velocity within 1e-6 of the
  // largest velocity, with a divergence-free part and a gradient part of the same size.
  QuasiStokesProjection proj(m, PressurePreconditioner::schur, 1e-12, 50);
  ImplicitDiffusion diffusion(m, 1000.0, 1.2e-3, 3e-6);
  CouplingProducts single_products(m, diffusion, proj, 1000.0, 3e-6, CouplingProducts::Precision::kSingleWherePossible);
  ASSERT_TRUE(single_products.single_precision());
  VelocityField u(m);
  const std::vector<double> r1 = random_vector(m.velocity_nodes(), 7), r2 = random_vector(m.velocity_nodes(), 8);
  for (int j = 1; j < m.ny; ++j)
    for (int i = 0; i < m.nx; ++i) {
      u.u1[m.v(i, j)] = std::sin(0.3 * j) + r1[m.v(i, j)];
      u.u2[m.v(i, j)] = r2[m.v(i, j)];
    }
  VelocityField pd(m), ps(m);
  std::vector<double> pressure;
  proj.project(u, pd, pressure, 1000.0, 3e-6, ProjectionForm::exact);
  single_products.project(u, ps);
  const double e = std::max(largest_difference(pd.u1, ps.u1), largest_difference(pd.u2, ps.u2));
  std::printf("projection: single against double %.2e of the largest velocity\n", e);
  EXPECT_LT(e, 1e-6);
  EXPECT_GT(e, 0.0);
}

TEST(FastSolvers, RowsFartherApartThanTwiceTheBandAreProbedTogetherAndAWiderBandNearAWallIsProbedRowByRow) {
  // Step 4's operator (band 1) on the wide grid is read in 6 products (the middle row, four sets of
  // rows 4 apart, the check) instead of 159. The same operator with row 0 coupled to row 3 (band 3
  // at the wall only: a response farther than 1 from every probed row) or to row 4 (a response on
  // another probed row, which only the check on a pseudo-random field finds: 1 + 4 + 1 products)
  // is then probed one row at a time. Claim: each solves to round-off (residual within 1e-13 of the
  // largest right-hand side).
  const ChannelMesh m = ChannelMesh::make(100e-6, 50e-6, 0.3125e-6);
  const int nx = m.nx, rows = m.ny - 1;
  for (const int coupled : {0, 3, 4}) {
    int products = 0;
    auto apply = [&](const std::vector<double>& in, std::vector<double>& out) {
      ++products;
      for (int r = 0; r < rows; ++r)
        for (int i = 0; i < nx; ++i) {
          double s = 6.0 * in[r * nx + i] - (in[r * nx + (i + 1) % nx] + in[r * nx + (i + nx - 1) % nx]);
          if (r > 0) s -= in[(r - 1) * nx + i];
          if (r + 1 < rows) s -= in[(r + 1) * nx + i];
          if (coupled && r == 0) s -= 0.5 * in[coupled * nx + i];
          if (coupled && r == coupled) s -= 0.5 * in[i];
          out[r * nx + i] = s;
        }
    };
    PeriodicBandedSolver solver(nx, rows, apply, false);
    EXPECT_EQ(solver.half_bandwidth(), coupled ? coupled : 1);
    // With row 3 coupled, the set of row 3 finds row 0's response before the check.
    const int expected = coupled == 0 ? 6 : coupled == 3 ? 1 + 4 + rows : 1 + 4 + 1 + rows;
    EXPECT_EQ(products, expected);
    EXPECT_LT(largest_residual(solver, apply, random_vector(std::size_t(nx) * rows, 9)), 1e-13);
  }
}

TEST(FastSolvers, RowsProbedTogetherGiveTheTapsOfOneProbePerRowBitForBit) {
  // Claim: the same taps (values and order) as one probe per row, for step 4's operator on the wide
  // grid and the Schur complement B M⁻¹ Bᵀ on its coarse grid (band 2).
  const ChannelMesh m = ChannelMesh::make(100e-6, 50e-6, 0.3125e-6);
  ImplicitDiffusion diffusion(m, 1000.0, 1.2e-3, 3e-6);
  const DivergenceStencil B(m);
  const PeriodicBandedSolver::Operator schur = schur_complement(m, B);
  const auto helmholtz = diffusion.helmholtz_operator();
  const auto a = detail::probe_taps(m.nx, m.ny - 1, helmholtz), b = detail::probe_taps(m.nx, m.ny - 1, helmholtz, true);
  const auto c = detail::probe_taps(m.pnx(), m.pny(), schur), d = detail::probe_taps(m.pnx(), m.pny(), schur, true);
  EXPECT_EQ(a.size(), std::size_t(m.ny - 1) * 5 - 2);  // five taps a row, four in the rows next to the walls
  EXPECT_EQ(a, b);
  EXPECT_GT(c.size(), a.size() / 4);
  EXPECT_EQ(c, d);
}

TEST(FastSolvers, ASolverFromAnotherSolversFactorsIsTheSolverOfItsOperatorBitForBit) {
  // The GMRES products' single-precision solvers take the fluid's double solvers' factors
  // (coupling_products.cpp) instead of probing the same operators again. Claim: the same solves,
  // bit for bit, as a single-precision solver built from the operator; for step 4's operator and
  // for the Schur complement (a constant kernel).
  const ChannelMesh m = ChannelMesh::make(20e-6, 10e-6, 0.3125e-6);
  ImplicitDiffusion diffusion(m, 1000.0, 1.2e-3, 3e-6);
  QuasiStokesProjection proj(m, PressurePreconditioner::schur, 1e-12, 50);
  const DivergenceStencil B(m);
  const PeriodicBandedSolver::Operator schur = schur_complement(m, B);
  struct Case { const PeriodicBandedSolver& factored; PeriodicBandedSolver::Operator apply; int nx, rows; bool constant_kernel; };
  for (const Case& c : {Case{diffusion.helmholtz(), diffusion.helmholtz_operator(), m.nx, m.ny - 1, false},
                        Case{proj.schur_solver(), schur, m.pnx(), m.pny(), true}}) {
    SinglePeriodicBandedSolver probed(c.nx, c.rows, c.apply, c.constant_kernel), taken(FactorsOf{c.factored});
    std::vector<double> b = random_vector(std::size_t(c.nx) * c.rows, 10);
    if (c.constant_kernel) {  // compatible: zero sum
      double mean = 0;
      for (double v : b) mean += v / double(b.size());
      for (double& v : b) v -= mean;
    }
    std::vector<double> x(b.size()), y(b.size());
    probed.solve(b.data(), x.data());
    taken.solve(b.data(), y.data());
    EXPECT_EQ(x, y);
  }
}

TEST(FastSolvers, AnOperatorNotSymmetricInX1TakesTheComplexPathAndStillSolves) {
  // Step 4's operator plus an upwind-like x1 difference (a(1) ≠ a(−1)): a complex symbol.
  const int nx = 16, rows = 7;
  auto apply = [=](const std::vector<double>& in, std::vector<double>& out) {
    for (int r = 0; r < rows; ++r)
      for (int i = 0; i < nx; ++i) {
        double s = 5.0 * in[r * nx + i] - 1.5 * in[r * nx + (i + 1) % nx] - 0.5 * in[r * nx + (i + nx - 1) % nx];
        if (r > 0) s -= in[(r - 1) * nx + i];
        if (r + 1 < rows) s -= in[(r + 1) * nx + i];
        out[r * nx + i] = s;
      }
  };
  PeriodicBandedSolver solver(nx, rows, apply, false);
  EXPECT_FALSE(solver.real_symbol());
  EXPECT_LT(largest_residual(solver, apply, random_vector(std::size_t(nx) * rows, 4)), 1e-13);
}

TEST(FastSolvers, SchurComplementSolveMatchesSparseLUUpToTheConstant) {
  // S = B M⁻¹ Bᵀ over the interior velocity nodes, built here as a sparse product; its kernel is
  // the constants, so we pin the last pressure node for LU and compare mean-free solutions.
  const ChannelMesh m = ChannelMesh::make(12e-6, 8e-6, 0.5e-6);
  const SparseMatrix B = assemble_divergence(m);
  const std::size_t nv = m.velocity_nodes();
  Eigen::VectorXd minv = Eigen::VectorXd::Zero(2 * nv);
  for (int j = 1; j < m.ny; ++j)
    for (int i = 0; i < m.nx; ++i) minv[m.v(i, j)] = minv[nv + m.v(i, j)] = 1.0 / (m.h * m.h);
  const Eigen::SparseMatrix<double> S = (B * minv.asDiagonal() * SparseMatrix(B.transpose())).pruned();
  const int np = int(S.rows());
  // A compatible right-hand side: the divergence of a random velocity field.
  std::vector<double> uu = random_vector(2 * nv, 2);
  for (int i = 0; i < m.nx; ++i) uu[nv + m.v(i, 0)] = uu[nv + m.v(i, m.ny)] = 0.0;  // no flux through the walls
  const Eigen::VectorXd b = B * Eigen::Map<const Eigen::VectorXd>(uu.data(), Eigen::Index(uu.size()));
  Eigen::SparseMatrix<double> Sp = S.topLeftCorner(np - 1, np - 1);
  Eigen::SparseLU<Eigen::SparseMatrix<double>> lu(Sp);
  Eigen::VectorXd ref = Eigen::VectorXd::Zero(np);
  ref.head(np - 1) = lu.solve(b.head(np - 1));

  QuasiStokesProjection proj(m, PressurePreconditioner::schur, 1e-12, 50);
  PeriodicBandedSolver fast(
      m.pnx(), m.pny(),
      [&S](const std::vector<double>& in, std::vector<double>& out) {
        Eigen::Map<Eigen::VectorXd>(out.data(), Eigen::Index(out.size())) =
            S * Eigen::Map<const Eigen::VectorXd>(in.data(), Eigen::Index(in.size()));
      },
      true);
  EXPECT_EQ(fast.half_bandwidth(), 2);  // P1-iso-P2: coarse rows J, J' couple for |J − J'| ≤ 2
  std::vector<double> x(np), r(ref.data(), ref.data() + np);
  fast.solve(b.data(), x.data());
  proj.remove_mean(x);
  proj.remove_mean(r);
  double e = 0, s = 0;
  for (int k = 0; k < np; ++k) { e = std::max(e, std::abs(x[k] - r[k])); s = std::max(s, std::abs(r[k])); }
  EXPECT_LT(e, 1e-9 * s);
}

TEST(FastSolvers, NeumannLaplacianSolveHasZeroResidual) {
  // The study's preconditioner, the P1 Neumann Laplacian of T_2h: K x = b for compatible b.
  const SparseMatrix K = assemble_p1_stiffness(10, 6);
  PeriodicBandedSolver fast(
      10, 7,
      [&K](const std::vector<double>& in, std::vector<double>& out) {
        Eigen::Map<Eigen::VectorXd>(out.data(), Eigen::Index(out.size())) =
            K * Eigen::Map<const Eigen::VectorXd>(in.data(), Eigen::Index(in.size()));
      },
      true);
  EXPECT_EQ(fast.half_bandwidth(), 1);
  std::vector<double> b = random_vector(70, 3), x(70);
  double mean = 0;
  for (double v : b) mean += v / 70;
  for (double& v : b) v -= mean;  // compatible: Σ b = 0 (the kernel of Kᵀ is the constants)
  fast.solve(b.data(), x.data());
  const Eigen::VectorXd r = K * Eigen::Map<const Eigen::VectorXd>(x.data(), 70) - Eigen::Map<const Eigen::VectorXd>(b.data(), 70);
  EXPECT_LT(r.lpNorm<Eigen::Infinity>(), 1e-12);
}

TEST(FemOperators, StiffnessIsTheFivePointLaplacianInside) {
  const SparseMatrix K = assemble_p1_stiffness(8, 6);
  const int n = 3 * 8 + 4;  // node (4, 3)
  EXPECT_DOUBLE_EQ(K.coeff(n, n), 4.0);
  for (int nb : {n - 1, n + 1, n - 8, n + 8}) EXPECT_DOUBLE_EQ(K.coeff(n, nb), -1.0);
  EXPECT_DOUBLE_EQ(K.coeff(n, n + 9), 0.0);
  EXPECT_DOUBLE_EQ(K.coeff(n, n - 7), 0.0);
}

TEST(FemOperators, DivergenceOfAConstantOrRigidTranslationVanishes) {
  // ∫ q ∇·u = 0 for u = constant (periodic in x1; u2 = 0 on the walls is not needed for ∇·u = 0).
  const ChannelMesh m = ChannelMesh::make(6e-6, 4e-6, 0.5e-6);
  const SparseMatrix B = assemble_divergence(m);
  Eigen::VectorXd u = Eigen::VectorXd::Zero(B.cols());
  u.head(m.velocity_nodes()).setConstant(0.3);
  EXPECT_LT((B * u).lpNorm<Eigen::Infinity>(), 1e-20);
  // And ∫ 1 ∇·u = boundary flux: Σ_Q (B u)_Q = 0 when u2 vanishes on the walls.
  const std::vector<double> r = random_vector(B.cols(), 4);
  Eigen::VectorXd v = Eigen::Map<const Eigen::VectorXd>(r.data(), Eigen::Index(r.size()));
  for (int i = 0; i < m.nx; ++i) v[m.velocity_nodes() + m.v(i, 0)] = v[m.velocity_nodes() + m.v(i, m.ny)] = 0;
  EXPECT_LT(std::abs((B * v).sum()), 1e-18);
}

TEST(ChannelMeshInput, MeshSizeThatDoesNotDivideTheChannelIsRejectedNamingTheSide) {
  try {
    ChannelMesh::make(20e-6, 10e-6, 0.3e-6);
    FAIL() << "expected an exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("length"), std::string::npos) << e.what();
  }
  try {
    ChannelMesh::make(20e-6, 10.1e-6, 0.5e-6);
    FAIL() << "expected an exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("height"), std::string::npos) << e.what();
  }
  EXPECT_THROW(ChannelMesh::make(20e-6, 10e-6, -1.0), std::invalid_argument);
  EXPECT_THROW(ChannelMesh::make(3e-6, 10e-6, 1e-6), std::invalid_argument);  // 3 cells: odd
}

}  // namespace
}  // namespace rbc

namespace rbc {
namespace {

TEST(FemOperators, DivergenceStencilEqualsTheAssembledMatrixAndItsTranspose) {
  // The matrix-free B = R D and Bᵀ agree with the element-by-element assembly to round-off, and
  // give the same bits on any number of threads (each thread sweeps its own rows and makes the
  // rows at the edge of its share again: 3 and 5 threads cut the rows unevenly, down to one
  // coarse row a thread).
  const ChannelMesh m = ChannelMesh::make(6e-6, 4e-6, 0.5e-6);
  const SparseMatrix B = assemble_divergence(m);
  const DivergenceStencil S(m);
  const std::size_t nv = m.velocity_nodes();
  const std::vector<double> u = random_vector(2 * nv, 5);
  const std::vector<double> u1(u.begin(), u.begin() + nv), u2(u.begin() + nv, u.end());
  const std::vector<double> p = random_vector(m.pressure_nodes(), 6);
  const Eigen::VectorXd ref = B * Eigen::Map<const Eigen::VectorXd>(u.data(), Eigen::Index(u.size()));
  const Eigen::VectorXd gt = B.transpose() * Eigen::Map<const Eigen::VectorXd>(p.data(), Eigen::Index(p.size()));
  const double scale = ref.lpNorm<Eigen::Infinity>(), gs = gt.lpNorm<Eigen::Infinity>();
  const int threads = omp_get_max_threads();
  std::vector<double> div_one, g1_one, g2_one;
  for (int t : {1, 2, 3, 5}) {
    omp_set_num_threads(t);
    std::vector<double> div, g1, g2;
    S.apply(u1, u2, div);
    S.apply_transpose(p, g1, g2);
    ASSERT_EQ(div.size(), m.pressure_nodes());
    for (Eigen::Index q = 0; q < ref.size(); ++q) EXPECT_NEAR(div[q], ref[q], 1e-13 * scale) << t << " threads";
    for (int j = 1; j < m.ny; ++j)
      for (int i = 0; i < m.nx; ++i) {
        EXPECT_NEAR(g1[m.v(i, j)], gt[m.v(i, j)], 1e-13 * gs) << t << " threads";
        EXPECT_NEAR(g2[m.v(i, j)], gt[nv + m.v(i, j)], 1e-13 * gs) << t << " threads";
      }
    for (int i = 0; i < m.nx; ++i)  // the wall rows are not unknowns: zero
      EXPECT_TRUE(g1[m.v(i, 0)] == 0 && g2[m.v(i, 0)] == 0 && g1[m.v(i, m.ny)] == 0 && g2[m.v(i, m.ny)] == 0);
    if (t == 1) {
      div_one = div, g1_one = g1, g2_one = g2;
    } else {
      EXPECT_EQ(div, div_one) << t << " threads";
      EXPECT_EQ(g1, g1_one) << t << " threads";
      EXPECT_EQ(g2, g2_one) << t << " threads";
    }
  }
  omp_set_num_threads(threads);
}

TEST(FemOperators, TheProjectionsUpdateSweepIsTheVelocityPlusTheScaledTranspose) {
  // add_transpose (the projection's out = u + c Bᵀ p, in Bᵀ's own sweep) against apply_transpose
  // and the sum made apart: equal to round-off of the sum (1e-15 of its size; a wrong node or
  // row errs by O(1)), the wall rows exactly u, in place as well, and the same bits on 1, 2, 3
  // and 5 threads.
  const ChannelMesh m = ChannelMesh::make(6e-6, 4e-6, 0.5e-6);
  const DivergenceStencil S(m);
  const std::size_t nv = m.velocity_nodes();
  const std::vector<double> u = random_vector(2 * nv, 7), p = random_vector(m.pressure_nodes(), 8);
  const std::vector<double> u1(u.begin(), u.begin() + nv), u2(u.begin() + nv, u.end());
  const double c = 0.37;
  std::vector<double> g1, g2;
  S.apply_transpose(p, g1, g2);
  const int threads = omp_get_max_threads();
  std::vector<double> one1, one2;
  for (int t : {1, 2, 3, 5}) {
    omp_set_num_threads(t);
    std::vector<double> o1, o2;
    S.add_transpose(p, c, u1, u2, o1, o2);
    ASSERT_EQ(o1.size(), nv);
    for (std::size_t k = 0; k < nv; ++k) {
      EXPECT_NEAR(o1[k], u1[k] + c * g1[k], 1e-15 * (std::abs(u1[k]) + std::abs(c * g1[k]))) << k << ", " << t << " threads";
      EXPECT_NEAR(o2[k], u2[k] + c * g2[k], 1e-15 * (std::abs(u2[k]) + std::abs(c * g2[k]))) << k << ", " << t << " threads";
    }
    for (int i = 0; i < m.nx; ++i)
      EXPECT_TRUE(o1[m.v(i, 0)] == u1[m.v(i, 0)] && o2[m.v(i, m.ny)] == u2[m.v(i, m.ny)]);
    std::vector<double> in1 = u1, in2 = u2;  // in place
    S.add_transpose(p, c, in1, in2, in1, in2);
    EXPECT_EQ(in1, o1) << t << " threads";
    EXPECT_EQ(in2, o2) << t << " threads";
    if (t == 1) {
      one1 = o1, one2 = o2;
    } else {
      EXPECT_EQ(o1, one1) << t << " threads";
      EXPECT_EQ(o2, one2) << t << " threads";
    }
  }
  omp_set_num_threads(threads);
}

}  // namespace
}  // namespace rbc
