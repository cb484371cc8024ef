#include "fluid/diffusion.hpp"

namespace rbc {

ImplicitDiffusion::ImplicitDiffusion(const ChannelMesh& mesh, double rho, double mu, double dt)
    : m_(mesh), rho_(rho), mu_(mu), dt_(dt), rhs_(std::size_t(mesh.nx) * (mesh.ny - 1), 0.0), rhs2_(rhs_.size(), 0.0) {
  solver_ = std::make_unique<PeriodicBandedSolver>(mesh.nx, mesh.ny - 1, helmholtz_operator(), false);
}

PeriodicBandedSolver::Operator ImplicitDiffusion::helmholtz_operator() const {
  // The Helmholtz operator on the interior rows j = 1..ny-1 (stored as rows 0..ny-2);
  // wall neighbours are known values and move to the right-hand side.
  const int nx = m_.nx, rows = m_.ny - 1;
  const double diag = rho_ * m_.h * m_.h / dt_ + 4.0 * mu_, mu = mu_;
  return [=](const std::vector<double>& in, std::vector<double>& out) {
    for (int r = 0; r < rows; ++r)
      for (int i = 0; i < nx; ++i) {
        const int ip = (i + 1) % nx, im = (i + nx - 1) % nx;
        double s = diag * in[r * nx + i] - mu * (in[r * nx + ip] + in[r * nx + im]);
        if (r > 0) s -= mu * in[(r - 1) * nx + i];
        if (r + 1 < rows) s -= mu * in[(r + 1) * nx + i];
        out[r * nx + i] = s;
      }
  };
}

void ImplicitDiffusion::diffuse(VelocityField& u, const double body_force[2], const VelocityField* field) {
  const int nx = m_.nx, rows = m_.ny - 1;
  const double h2 = m_.h * m_.h, a = rho_ * h2 / dt_;
  for (int c = 0; c < 2; ++c) {
    std::vector<double>& f = (c == 0) ? u.u1 : u.u2;
    std::vector<double>& rhs = (c == 0) ? rhs_ : rhs2_;
    const std::vector<double>* extra = field ? (c == 0 ? &field->u1 : &field->u2) : nullptr;
    const double* bottom = &f[0];
    const double* top = &f[std::size_t(m_.ny) * nx];
#pragma omp parallel for schedule(static)
    for (int r = 0; r < rows; ++r) {
      const std::size_t o = std::size_t(r + 1) * nx;  // node row j = r + 1
      double* out = &rhs[std::size_t(r) * nx];
      for (int i = 0; i < nx; ++i) out[i] = a * f[o + i] + h2 * (body_force[c] + (extra ? (*extra)[o + i] : 0.0));
      if (r == 0)
        for (int i = 0; i < nx; ++i) out[i] += mu_ * bottom[i];
      if (r + 1 == rows)
        for (int i = 0; i < nx; ++i) out[i] += mu_ * top[i];
    }
  }
  solve_pair(rhs_.data(), rhs2_.data());  // both components at once
#pragma omp parallel for schedule(static)
  for (int k = 0; k < nx * rows; ++k) {
    u.u1[nx + k] = rhs_[k];
    u.u2[nx + k] = rhs2_[k];
  }
}

void ImplicitDiffusion::add_force_response(VelocityField& u, const VelocityField& field) {
  const int nx = m_.nx, rows = m_.ny - 1;
  const double h2 = m_.h * m_.h;
  const int n = nx * rows;
#pragma omp parallel for schedule(static)
  for (int k = 0; k < n; ++k) {
    rhs_[k] = h2 * field.u1[nx + k];
    rhs2_[k] = h2 * field.u2[nx + k];
  }
  solve_pair(rhs_.data(), rhs2_.data());
#pragma omp parallel for schedule(static)
  for (int k = 0; k < n; ++k) {
    u.u1[nx + k] += rhs_[k];
    u.u2[nx + k] += rhs2_[k];
  }
}

void ImplicitDiffusion::solve_pair(double* b1, double* b2) {
  if (constraint_) constraint_->solve_pair(b1, b2);
  else solver_->solve_pair(b1, b2, b1, b2);
}

void ImplicitDiffusion::solve_interior(double* b) { solver_->solve(b, b); }

}  // namespace rbc
