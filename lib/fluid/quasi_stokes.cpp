#include "fluid/quasi_stokes.hpp"

#include "fem/p1_operators.hpp"

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
// b *= c, elementwise: the threads share it.
void scale(std::vector<double>& b, double c) {
  const std::ptrdiff_t size = std::ptrdiff_t(b.size());
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t k = 0; k < size; ++k) b[k] *= c;
}
}  // namespace

PressurePreconditioner parse_pressure_preconditioner(const std::string& name) {
  if (name == "schur") return PressurePreconditioner::schur;
  if (name == "laplacian") return PressurePreconditioner::laplacian;
  throw std::invalid_argument("unknown pressure preconditioner '" + name + "' (allowed: schur, laplacian)");
}

QuasiStokesProjection::QuasiStokesProjection(const ChannelMesh& mesh, PressurePreconditioner pc, double tolerance,
                                             int max_iterations)
    : mesh_(mesh), B_(mesh), inv_mass_(1.0 / (mesh.h * mesh.h)), tol_(tolerance), max_it_(max_iterations) {
  // Each row of B sums |entries| to about 4h (measured on the assembled matrix: 3.5h inside).
  row_abs_norm_ = 4.0 * mesh.h * std::sqrt(double(mesh.pressure_nodes()));
  weights_.assign(mesh.pressure_nodes(), 0.0);
  for (int J = 0; J < mesh.pny(); ++J)
    for (int I = 0; I < mesh.pnx(); ++I) weights_[mesh.p(I, J)] = (J == 0 || J == mesh.pny() - 1) ? 0.5 : 1.0;
  for (double w : weights_) total_weight_ += w;
  for (auto* v : {&r_, &z_, &d_, &sd_, &b_}) v->assign(mesh.pressure_nodes(), 0.0);

  exact_pc_ = (pc == PressurePreconditioner::schur);
  if (exact_pc_) {
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

const PeriodicBandedSolver& QuasiStokesProjection::schur_solver() const {
  if (!exact_pc_) throw std::logic_error("QuasiStokesProjection::schur_solver: the preconditioner is not the exact Schur solve");
  return *pc_;
}

void QuasiStokesProjection::apply_schur(const std::vector<double>& p, std::vector<double>& out) const {
  // S p = B M⁻¹ Bᵀ p.
  B_.apply_transpose(p, g1_, g2_);
  for (std::size_t n = 0; n < g1_.size(); ++n) { g1_[n] *= inv_mass_; g2_[n] *= inv_mass_; }
  B_.apply(g1_, g2_, out);
}

void QuasiStokesProjection::remove_mean(std::vector<double>& p) const {
  // The weighted sum in node order on one thread (its bits do not depend on the threads); the
  // weights' own sum is the constructor's, in the same order.
  double s = 0;
  for (std::size_t k = 0; k < p.size(); ++k) s += weights_[k] * p[k];
  const double mean = s / total_weight_;
  const std::ptrdiff_t size = std::ptrdiff_t(p.size());
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t k = 0; k < size; ++k) p[k] -= mean;
}


void QuasiStokesProjection::precondition(const std::vector<double>& r, std::vector<double>& z) {
  pc_->solve(r.data(), z.data());
  remove_mean(z);
}

void QuasiStokesProjection::divergence(const VelocityField& u, std::vector<double>& div) const {
  B_.apply(u.u1, u.u2, div);
}

ProjectionReport QuasiStokesProjection::project(const VelocityField& u, VelocityField& out, std::vector<double>& p, double rho,
                                                double dt, ProjectionForm form, const SchurSolve& schur_solve) {
  // The pressure, then the velocity update out = u + (Δt/ρ) M⁻¹ Bᵀ p (none for a divergence at
  // round-off level).
  ProjectionReport rep;
  if (solve_pressure(u, p, rho, dt, form, schur_solve, rep))
    add_pressure_gradient(u, p, rho, dt, out);
  else if (&out != &u)
    out = u;
  return rep;
}

ProjectionReport QuasiStokesProjection::pressure(const VelocityField& u, std::vector<double>& p, double rho, double dt,
                                                 ProjectionForm form, const SchurSolve& schur_solve) {
  ProjectionReport rep;
  solve_pressure(u, p, rho, dt, form, schur_solve, rep);
  return rep;
}

bool QuasiStokesProjection::solve_pressure(const VelocityField& u, std::vector<double>& p, double rho, double dt,
                                           ProjectionForm form, const SchurSolve& schur_solve, ProjectionReport& rep) {
  if (schur_solve && !(exact_pc_ && form == ProjectionForm::exact))
    throw std::logic_error("QuasiStokesProjection: a caller's S⁻¹ needs the exact form and the Schur preconditioner");
  if (p.size() != mesh_.pressure_nodes()) p.assign(mesh_.pressure_nodes(), 0.0);
  // Right-hand side b = −(ρ/Δt) B uⁿ.
  std::vector<double>& b = b_;
  divergence(u, b);
  scale(b, -rho / dt);
  // The exact form with the exact Schur preconditioner is one fast solve and nothing else; every
  // other case checks the divergence first. A divergence at round-off level (a parallel flow)
  // needs no correction: compare ‖b‖ with the size its terms have, (ρ/Δt) max|u| ‖row sums of |B|‖.
  const bool one_solve = form == ProjectionForm::exact && exact_pc_;
  if (form == ProjectionForm::exact && !exact_pc_) p.assign(p.size(), 0.0);  // no exact solve: CG from p = 0
  double bnorm = 0, floor = 0;
  if (!one_solve) {
    bnorm = std::sqrt(dot(b, b));
    double umax = 0;  // a maximum is exact in any order: the threads share it
    const std::ptrdiff_t size = std::ptrdiff_t(u.u1.size());
#pragma omp parallel for schedule(static) reduction(max : umax)
    for (std::ptrdiff_t n = 0; n < size; ++n) umax = std::max({umax, std::abs(u.u1[n]), std::abs(u.u2[n])});
    floor = 1e-13 * rho / dt * umax * row_abs_norm_;
    if (bnorm <= floor) {
      p.assign(p.size(), 0.0);
      return false;
    }
  }
  // Preconditioned conjugate gradients on S p = b. With the exact Schur preconditioner the first
  // iteration from p = 0 solves the system, p = α S⁻¹ b with α = 1 to round-off: we take p = S⁻¹ b
  // (one iteration, in either form), without the S product that α and the residual check cost
  // (Bᵀ and B, a third of the projection). S⁻¹ is a fixed factorisation of S, exact to round-off
  // at every step (tests: DiscreteDivergenceAfterProjectionIsBelowTheCgTolerance,
  // TheExactProjectionIsTheProjectionWithoutItsResidualCheck); the residual is then not measured
  // (NaN). With the study's Laplacian preconditioner we start from the previous pressure (warm
  // start) and iterate to the tolerance.
  if (exact_pc_) {
    if (schur_solve) {  // the caller's S⁻¹
      schur_solve(b.data(), p.data());
      remove_mean(p);
    } else {
      precondition(b, p);
    }
    rep.iterations = 1;
    rep.residual = NAN;
    return true;
  }
  apply_schur(p, r_);
  for (std::size_t k = 0; k < r_.size(); ++k) r_[k] = b[k] - r_[k];
  double rnorm = std::sqrt(dot(r_, r_));
  const double target = std::max(tol_ * bnorm, floor);
  if (rnorm > target) {
    precondition(r_, z_);
    d_ = z_;
    double rz = dot(r_, z_);
    std::vector<double>& sd = sd_;
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
  rep.converged = rnorm <= target;
  remove_mean(p);
  return true;
}

void QuasiStokesProjection::add_pressure_gradient(const VelocityField& u, const std::vector<double>& p, double rho,
                                                  double dt, VelocityField& out) {
  // Velocity update on the interior: out = u + (Δt/ρ) M⁻¹ Bᵀ p (Bᵀ p is zero on the walls), in
  // the same sweep as Bᵀ p.
  B_.add_transpose(p, dt / rho * inv_mass_, u.u1, u.u2, out.u1, out.u2);
}

void QuasiStokesProjection::pressure_force(const std::vector<double>& p, VelocityField& out) {
  B_.apply_transpose(p, out.u1, out.u2);
  const std::ptrdiff_t size = std::ptrdiff_t(out.u1.size());
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t n = 0; n < size; ++n) {
    out.u1[n] *= inv_mass_;
    out.u2[n] *= inv_mass_;
  }
}

void QuasiStokesProjection::projected_at(const VelocityField& u, const std::vector<double>& p, double rho, double dt, int i, int j,
                                         double& v1, double& v2) const {
  // add_pressure_gradient's value at the one node (the walls: u).
  const std::size_t n = std::size_t(j) * mesh_.nx + i;
  if (j <= 0 || j >= mesh_.ny) {
    v1 = u.u1[n];
    v2 = u.u2[n];
    return;
  }
  const double c = dt / rho * inv_mass_;
  double g1, g2;
  B_.transpose_at(p, i, j, g1, g2);
  v1 = u.u1[n] + c * g1;
  v2 = u.u2[n] + c * g2;
}

}  // namespace rbc
