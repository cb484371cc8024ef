#include "immersed_boundary/semi_implicit_coupling.hpp"

#include <algorithm>

#include "immersed_boundary/immersed_boundary.hpp"
#include "membrane/membrane_stiffness.hpp"

namespace rbc {

SemiImplicitMembraneStep::SemiImplicitMembraneStep(ChannelFlow& flow, const MembraneModel& model)
    : flow_(flow),
      mesh_(flow.mesh()),
      model_(model),
      dt_(flow.params().dt),
      projected_(flow.mesh()),
      pressure_(flow.mesh().pressure_nodes(), 0.0),
      move_(flow.mesh(), model),
      mobility_(flow.mesh(), flow.diffusion(), flow.projection(), flow.params().fluid.density, flow.params().dt),
      correction_(flow.mesh()) {}

const VelocityField& SemiImplicitMembraneStep::implicit_correction(const std::vector<Cell>& cells, const VelocityField& u) {
  std::fill(correction_.u1.begin(), correction_.u1.end(), 0.0);
  std::fill(correction_.u2.begin(), correction_.u2.end(), 0.0);
  const int ncells = int(cells.size());
  std::vector<Points> dF(ncells);
  // P u⁰: the velocity step 1 would hand to step 2 without the correction.
  projected_ = u;
  flow_.projection().project(projected_, pressure_, flow_.params().fluid.density, dt_);
#pragma omp parallel for schedule(dynamic)
  for (int c = 0; c < ncells; ++c) {
    const Points& r = cells[c].nodes;
    const int n = int(r.size());
    // U⁰ = J P u⁰ at the nodes, unknowns (x_1, y_1, x_2, …).
    Points U0;
    interpolate_velocity(mesh_, projected_, r, U0);
    const Eigen::VectorXd rhs = Eigen::Map<const Eigen::VectorXd>(U0[0].data(), 2 * n);
    // I + Δt M K.
    Eigen::MatrixXd M;
    mobility_.matrix(r, M);
    const Eigen::MatrixXd K = membrane_stiffness(model_, r, cells[c].target_area);
    Eigen::MatrixXd A = dt_ * (M * K);
    A.diagonal().array() += 1.0;
    const Eigen::VectorXd U = A.partialPivLu().solve(rhs);
    // ΔF = −Δt K U, the change of the spring force over the coming step.
    const Eigen::VectorXd f = -dt_ * (K * U);
    dF[c].resize(n);
    for (int i = 0; i < n; ++i) dF[c][i] = Eigen::Vector2d(f[2 * i], f[2 * i + 1]);
  }
  for (int c = 0; c < ncells; ++c) spread_forces(mesh_, cells[c].nodes, dF[c], correction_);
  return correction_;
}

}  // namespace rbc
