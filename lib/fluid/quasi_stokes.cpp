#include "fluid/quasi_stokes.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <Eigen/Core>

namespace rbc {

namespace {
using Vec = Eigen::Map<Eigen::VectorXd>;
using CVec = Eigen::Map<const Eigen::VectorXd>;
double dot(const std::vector<double>& a, const std::vector<double>& b) {
  return CVec(a.data(), Eigen::Index(a.size())).dot(CVec(b.data(), Eigen::Index(b.size())));
}
}  // namespace

PressurePreconditioner parse_pressure_preconditioner(const std::string& name) {
  if (name == "schur") return PressurePreconditioner::schur;
  if (name == "laplacian") return PressurePreconditioner::laplacian;
  throw std::invalid_argument("unknown pressure preconditioner '" + name + "' (allowed: schur, laplacian)");
}

QuasiStokesProjection::QuasiStokesProjection(const ChannelMesh& mesh, PressurePreconditioner pc, double tolerance,
                                             int max_iterations)
    : mesh_(mesh), B_(assemble_divergence(mesh)), tol_(tolerance), max_it_(max_iterations) {
  const std::size_t nv = mesh.velocity_nodes();
  inv_mass_.assign(2 * nv, 0.0);
  for (int j = 1; j < mesh.ny; ++j)
    for (int i = 0; i < mesh.nx; ++i) {
      inv_mass_[mesh.v(i, j)] = 1.0 / lumped_mass(mesh, j);
      inv_mass_[nv + mesh.v(i, j)] = 1.0 / lumped_mass(mesh, j);
    }
  // Bᵀ restricted to the interior velocity nodes: the walls are not unknowns.
  SparseMatrix Bt = B_.transpose();
  for (int k = 0; k < Bt.outerSize(); ++k)
    for (SparseMatrix::InnerIterator it(Bt, k); it; ++it)
      if (inv_mass_[it.row()] == 0.0) it.valueRef() = 0.0;
  Bt.prune(0.0);
  Bt_ = Bt;
  Eigen::VectorXd row_abs = Eigen::VectorXd::Zero(B_.rows());
  for (int k = 0; k < B_.outerSize(); ++k)
    for (SparseMatrix::InnerIterator it(B_, k); it; ++it) row_abs[k] += std::abs(it.value());
  row_abs_norm_ = row_abs.norm();
  weights_.assign(mesh.pressure_nodes(), 0.0);
  for (int J = 0; J < mesh.pny(); ++J)
    for (int I = 0; I < mesh.pnx(); ++I) weights_[mesh.p(I, J)] = (J == 0 || J == mesh.pny() - 1) ? 0.5 : 1.0;
  vel_.assign(2 * nv, 0.0);
  for (auto* v : {&r_, &z_, &d_, &sd_}) v->assign(mesh.pressure_nodes(), 0.0);

  if (pc == PressurePreconditioner::schur) {
    pc_ = std::make_unique<PeriodicBandedSolver>(
        mesh.pnx(), mesh.pny(), [this](const std::vector<double>& in, std::vector<double>& out) { apply_schur(in, out); },
        true);
  } else {
    const SparseMatrix K = assemble_p1_stiffness(mesh.pnx(), mesh.pny() - 1);
    pc_ = std::make_unique<PeriodicBandedSolver>(
        mesh.pnx(), mesh.pny(),
        [&K](const std::vector<double>& in, std::vector<double>& out) {
          Vec(out.data(), Eigen::Index(out.size())) = K * CVec(in.data(), Eigen::Index(in.size()));
        },
        true);
  }
}

void QuasiStokesProjection::apply_schur(const std::vector<double>& p, std::vector<double>& out) const {
  // S p = B M⁻¹ Bᵀ p.
  Vec v(vel_.data(), Eigen::Index(vel_.size()));
  v = Bt_ * CVec(p.data(), Eigen::Index(p.size()));
  v.array() *= CVec(inv_mass_.data(), Eigen::Index(inv_mass_.size())).array();
  Vec(out.data(), Eigen::Index(out.size())) = B_ * v;
}

void QuasiStokesProjection::remove_mean(std::vector<double>& p) const {
  double s = 0, w = 0;
  for (std::size_t k = 0; k < p.size(); ++k) { s += weights_[k] * p[k]; w += weights_[k]; }
  const double mean = s / w;
  for (double& x : p) x -= mean;
}

void QuasiStokesProjection::precondition(const std::vector<double>& r, std::vector<double>& z) {
  pc_->solve(r.data(), z.data());
  remove_mean(z);
}

void QuasiStokesProjection::divergence(const VelocityField& u, std::vector<double>& div) const {
  const std::size_t nv = mesh_.velocity_nodes();
  Eigen::VectorXd uu(2 * nv);
  uu.head(nv) = CVec(u.u1.data(), Eigen::Index(nv));
  uu.tail(nv) = CVec(u.u2.data(), Eigen::Index(nv));
  div.resize(mesh_.pressure_nodes());
  Vec(div.data(), Eigen::Index(div.size())) = B_ * uu;
}

ProjectionReport QuasiStokesProjection::project(VelocityField& u, std::vector<double>& p, double rho, double dt) {
  ProjectionReport rep;
  if (p.size() != mesh_.pressure_nodes()) p.assign(mesh_.pressure_nodes(), 0.0);
  // Right-hand side b = −(ρ/Δt) B uⁿ.
  std::vector<double>& b = sd_;
  divergence(u, b);
  for (double& x : b) x *= -rho / dt;
  const double bnorm = std::sqrt(dot(b, b));
  // A divergence at round-off level (a parallel flow) needs no correction: compare ‖b‖ with the
  // size its terms have, (ρ/Δt) max|u| ‖row sums of |B|‖.
  double umax = 0;
  for (std::size_t n = 0; n < u.u1.size(); ++n) umax = std::max({umax, std::abs(u.u1[n]), std::abs(u.u2[n])});
  const double floor = 1e-13 * rho / dt * umax * row_abs_norm_;
  if (bnorm <= floor) {
    p.assign(p.size(), 0.0);
    return rep;
  }
  // Preconditioned conjugate gradients on S p = b, from the warm start p.
  apply_schur(p, r_);
  for (std::size_t k = 0; k < r_.size(); ++k) r_[k] = b[k] - r_[k];
  double rnorm = std::sqrt(dot(r_, r_));
  const double target = std::max(tol_ * bnorm, floor);
  if (rnorm > target) {
    precondition(r_, z_);
    d_ = z_;
    double rz = dot(r_, z_);
    std::vector<double> sd(p.size());
    while (rep.iterations < max_it_) {
      apply_schur(d_, sd);
      const double curvature = dot(d_, sd);
      if (!(curvature > 0.0)) break;  // converged to round-off, or broken input
      const double alpha = rz / curvature;
      for (std::size_t k = 0; k < p.size(); ++k) { p[k] += alpha * d_[k]; r_[k] -= alpha * sd[k]; }
      ++rep.iterations;
      rnorm = std::sqrt(dot(r_, r_));
      if (rnorm <= target) break;
      precondition(r_, z_);
      const double rz_new = dot(r_, z_);
      const double beta = rz_new / rz;
      rz = rz_new;
      for (std::size_t k = 0; k < p.size(); ++k) d_[k] = z_[k] + beta * d_[k];
    }
  }
  rep.residual = rnorm / bnorm;
  remove_mean(p);
  // Velocity update on the interior: u = uⁿ + (Δt/ρ) M⁻¹ Bᵀ p.
  const std::size_t nv = mesh_.velocity_nodes();
  Vec g(vel_.data(), Eigen::Index(vel_.size()));
  g = Bt_ * CVec(p.data(), Eigen::Index(p.size()));
  for (std::size_t n = 0; n < nv; ++n) {
    u.u1[n] += dt / rho * inv_mass_[n] * vel_[n];
    u.u2[n] += dt / rho * inv_mass_[nv + n] * vel_[nv + n];
  }
  return rep;
}

}  // namespace rbc
