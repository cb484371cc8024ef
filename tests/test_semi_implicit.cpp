// The semi-implicit coupling (issue 4): the membrane stiffness, the mobility of step 4, and the
// coupling itself against the study's explicit scheme. Each test names the property it checks.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include <Eigen/Eigenvalues>

#include "diagnostics/cell_diagnostics.hpp"
#include "fluid/channel_flow.hpp"
#include "immersed_boundary/immersed_boundary.hpp"
#include "immersed_boundary/step_mobility.hpp"
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
  const Eigen::MatrixXd Ks = membrane_stiffness(stretch, r, 1.0), Hs = finite_difference_hessian(stretch, r, 1.0, eps);
  EXPECT_LT((Ks - Hs).norm(), 1e-6 * Hs.norm());
  MembraneModel area = m;
  area.kl = area.kb = 0;
  const double s_e = enclosed_area(r);
  const Eigen::MatrixXd Ka = membrane_stiffness(area, r, s_e), Ha = finite_difference_hessian(area, r, s_e, eps);
  EXPECT_LT((Ka - Ha).norm(), 1e-6 * Ha.norm());
}

TEST(MembraneStiffness, IsSymmetricPositiveSemiDefiniteAndCloseToTheHessianOnACompressedEllipse) {
  // The full model on a compressed, elongated 76-gon: the dropped parts (compressed springs'
  // transverse term, k_b t ∇²t, the area's curvature term) are small, and what is kept is ⪰ 0.
  const MembraneModel m = MembraneModel::from(MembraneConstants{}, 76, 2.8e-6);
  const Points r = polygon(76, 0.97 * 2.8e-6, 1.2);
  const double s_e = 0.9 * enclosed_area(r);
  const Eigen::MatrixXd K = membrane_stiffness(m, r, s_e), H = finite_difference_hessian(m, r, s_e, 1e-11);
  EXPECT_LT((K - K.transpose()).norm(), 1e-14 * K.norm());
  const Eigen::VectorXd ev = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(K).eigenvalues();
  EXPECT_GT(ev.minCoeff(), -1e-12 * ev.maxCoeff());
  const double rel = (K - H).norm() / H.norm();
  std::printf("|K - H| / |H| = %.3e on a compressed ellipse\n", rel);
  EXPECT_LT(rel, 0.1);
}

TEST(StepMobility, EqualsSpreadSolveProjectInterpolate) {
  // M F from the table against the long way (S, a fast solve of step 4, P, J),
  // for nodes near both walls, across the periodic boundary and in the bulk.
  ChannelFlowParams p;
  p.length = 10e-6;
  p.height = 5e-6;
  p.mesh_size = 0.25e-6;
  p.dt = 1e-6;
  ChannelFlow flow(p);
  const ChannelMesh& mesh = flow.mesh();
  StepMobility mobility(mesh, flow.diffusion(), flow.projection(), p.fluid.density, p.dt);
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
  flow.projection().project(w, pressure, p.fluid.density, p.dt);
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

}  // namespace
}  // namespace rbc
