#include "fluid/diffusion.hpp"

#include <stdexcept>

namespace rbc {

ImplicitDiffusion::ImplicitDiffusion(const ChannelMesh& mesh, double rho, double mu, double dt)
    : m_(mesh), rho_(rho), mu_(mu), dt_(dt), rhs_(std::size_t(mesh.nx) * (mesh.ny - 1), 0.0), rhs2_(rhs_.size(), 0.0) {
  solver_ = std::make_unique<PeriodicBandedSolver>(mesh.nx, mesh.ny - 1, helmholtz_operator(), false);
}

void ImplicitDiffusion::build_single_precision_solver() {
  if (!single_) single_ = std::make_unique<SinglePeriodicBandedSolver>(m_.nx, m_.ny - 1, helmholtz_operator(), false);
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
  solve_both(rhs_.data(), rhs2_.data());  // both components at once
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
  solve_both(rhs_.data(), rhs2_.data());
#pragma omp parallel for schedule(static)
  for (int k = 0; k < n; ++k) {
    u.u1[nx + k] += rhs_[k];
    u.u2[nx + k] += rhs2_[k];
  }
}

std::pair<double*, double*> ImplicitDiffusion::zeroed_force_rhs() {
  if (!rhs_zero_) {
    const std::ptrdiff_t n = std::ptrdiff_t(rhs_.size());
#pragma omp parallel for schedule(static)
    for (std::ptrdiff_t k = 0; k < n; ++k) rhs_[k] = rhs2_[k] = 0.0;
  }
  rhs_zero_ = false;  // the caller adds into them now
  return {rhs_.data(), rhs2_.data()};
}

void ImplicitDiffusion::force_response(VelocityField& out, bool single) {
  const int nx = m_.nx, n = nx * (m_.ny - 1);
  for (int k = 0; k < nx; ++k) out.u1[k] = out.u2[k] = out.u1[nx + n + k] = out.u2[nx + n + k] = 0.0;  // walls
  if (single && (constraint_ || !single_))
    throw std::logic_error("ImplicitDiffusion: a single-precision response needs build_single_precision_solver() and no constraint");
  if (!constraint_) {  // the fast solve writes the interior rows of out itself (no copy), and
    // clears the right-hand sides as it reads them: the next zeroed_force_rhs() has nothing to do
    // (the 50 cells' GMRES products: a memset of both fields, 3 % of the step's samples, saved).
    if (single) single_->solve_pair_clearing(rhs_.data(), rhs2_.data(), out.u1.data() + nx, out.u2.data() + nx);
    else solver_->solve_pair_clearing(rhs_.data(), rhs2_.data(), out.u1.data() + nx, out.u2.data() + nx);
    rhs_zero_ = true;
    return;
  }
  solve_both(rhs_.data(), rhs2_.data());
#pragma omp parallel for schedule(static)
  for (int k = 0; k < n; ++k) {
    out.u1[nx + k] = rhs_[k];
    out.u2[nx + k] = rhs2_[k];
  }
}

void ImplicitDiffusion::solve_interior(double* b) { solver_->solve(b, b); }

}  // namespace rbc
