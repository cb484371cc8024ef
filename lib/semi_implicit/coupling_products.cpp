#include "semi_implicit/coupling_products.hpp"

#include <algorithm>

namespace rbc {

CouplingProducts::CouplingProducts(const ChannelMesh& mesh, ImplicitDiffusion& diffusion, QuasiStokesProjection& projection, double rho,
                                   double dt, Precision precision)
    : mesh_(mesh),
      diffusion_(diffusion),
      projection_(projection),
      rho_(rho),
      dt_(dt),
      rhs1_(std::size_t(mesh.nx) * (mesh.ny - 1), 0.0),
      rhs2_(rhs1_.size(), 0.0),
      pressure_(mesh.pressure_nodes(), 0.0) {
  if (precision == Precision::kSingleWherePossible && !diffusion.constrained() && projection.exact_schur_solve()) {
    // The fluid's own solvers of the same two operators, their factors rounded.
    single_helmholtz_ = std::make_unique<SinglePeriodicBandedSolver>(FactorsOf{diffusion.helmholtz()});
    single_schur_ = std::make_unique<SinglePeriodicBandedSolver>(FactorsOf{projection.schur_solver()});
    schur_solve_ = [this](const double* r, double* z) { single_schur_->solve(r, z); };
  }
}

void CouplingProducts::response(VelocityField& out) {
  const int nx = mesh_.nx, n = nx * (mesh_.ny - 1);
  for (int k = 0; k < nx; ++k) out.u1[k] = out.u2[k] = out.u1[nx + n + k] = out.u2[nx + n + k] = 0.0;  // walls
  // The plain solve writes the interior rows of out itself and clears the right-hand sides as
  // it reads them; the constrained one works in place, so we copy and clear.
  if (single_helmholtz_) {
    single_helmholtz_->solve_pair_clearing(rhs1_.data(), rhs2_.data(), out.u1.data() + nx, out.u2.data() + nx);
    return;
  }
  if (!diffusion_.constrained()) {
    diffusion_.helmholtz().solve_pair_clearing(rhs1_.data(), rhs2_.data(), out.u1.data() + nx, out.u2.data() + nx);
    return;
  }
  diffusion_.solve_pair(rhs1_.data(), rhs2_.data());
#pragma omp parallel for schedule(static)
  for (int k = 0; k < n; ++k) {
    out.u1[nx + k] = rhs1_[k];
    out.u2[nx + k] = rhs2_[k];
    rhs1_[k] = rhs2_[k] = 0.0;
  }
}

void CouplingProducts::project(const VelocityField& u, VelocityField& out) {
  projection_.project(u, out, pressure_, rho_, dt_, ProjectionForm::exact, schur_solve_);
}

const std::vector<double>& CouplingProducts::pressure(const VelocityField& u) {
  projection_.pressure(u, pressure_, rho_, dt_, ProjectionForm::exact, schur_solve_);
  return pressure_;
}

}  // namespace rbc
