#include "fictitious_domain/dlm_obstacle_step.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "fictitious_domain/field_scans.hpp"

namespace rbc {

UzawaPreconditioner parse_uzawa_preconditioner(const std::string& name) {
  if (name == "capacitance") return UzawaPreconditioner::capacitance;
  if (name == "none") return UzawaPreconditioner::none;
  throw std::invalid_argument("unknown Uzawa preconditioner '" + name + "' (allowed: capacitance, none)");
}

ObstacleConstraint::ObstacleConstraint(const ObstacleGeometry& geometry, PeriodicBandedSolver& A, double tolerance,
                                       UzawaPreconditioner preconditioner, int max_iterations)
    : g_(geometry), A_(A), tolerance_(tolerance), preconditioner_(preconditioner), max_iterations_(max_iterations) {
  const auto t0 = std::chrono::steady_clock::now();
  const std::size_t n = std::size_t(A.nx()) * A.rows();
  for (int c = 0; c < 2; ++c) {
    work_[c].assign(n, 0.0);
    lambda_[c].assign(g_.nodes().size(), 0.0);
  }
  points_ = preconditioner_ == UzawaPreconditioner::capacitance ? g_.ring() : g_.nodes();
  for (int c = 0; c < 2; ++c) {
    rhs_[c].assign(n, 0.0);
    deep_lambda_[c].assign(g_.deep().size(), 0.0);
  }
  // Where each collocation node's multiplier comes from: its index among the CG's points, or
  // −1 − its index in D (capacitance: λ_D in closed form).
  {
    std::vector<int> at(n, std::numeric_limits<int>::min());
    for (std::size_t k = 0; k < points_.size(); ++k) at[std::size_t(points_[k])] = int(k);
    if (preconditioner_ == UzawaPreconditioner::capacitance)
      for (std::size_t k = 0; k < g_.deep().size(); ++k) at[std::size_t(g_.deep()[k])] = -1 - int(k);
    for (int node : g_.nodes()) where_.push_back(at[std::size_t(node)]);
  }
  if (preconditioner_ == UzawaPreconditioner::capacitance) {
    // S_R = (A⁻¹)_RR column by column, two ring nodes per fast solve pair.
    const int m = int(points_.size());
    Eigen::MatrixXd S(m, m);
    for (int k = 0; k < m; k += 2) {
      const int k2 = std::min(k + 1, m - 1);
      std::fill(work_[0].begin(), work_[0].end(), 0.0);
      std::fill(work_[1].begin(), work_[1].end(), 0.0);
      work_[0][std::size_t(points_[k])] = 1.0;
      work_[1][std::size_t(points_[k2])] = 1.0;
      A_.solve_pair(work_[0].data(), work_[1].data(), work_[0].data(), work_[1].data());
      for (int r = 0; r < m; ++r) {
        S(r, k) = work_[0][std::size_t(points_[r])];
        S(r, k2) = work_[1][std::size_t(points_[r])];
      }
    }
    S = 0.5 * (S + S.transpose()).eval();  // symmetric up to round-off
    capacitance_.compute(S);
    if (capacitance_.info() != Eigen::Success)
      throw std::runtime_error("fictitious domain: the capacitance matrix S_R is not positive definite");
  }
  setup_seconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

namespace {

// x ← x − α y over n values, returning max |x| of the result (the update and the field's scale in
// one pass).
double subtract_and_max_abs(double* x, const double* y, double alpha, std::size_t n) {
  double m[4] = {0, 0, 0, 0};
  std::size_t k = 0;
  for (; k + 4 <= n; k += 4)
    for (int l = 0; l < 4; ++l) {
      x[k + l] -= alpha * y[k + l];
      m[l] = std::max(m[l], std::abs(x[k + l]));
    }
  for (; k < n; ++k) {
    x[k] -= alpha * y[k];
    m[0] = std::max(m[0], std::abs(x[k]));
  }
  return std::max(std::max(m[0], m[1]), std::max(m[2], m[3]));
}

}  // namespace

void ObstacleConstraint::solve_pair(double* b1, double* b2) {
  double* b[2] = {b1, b2};
  const std::size_t n = work_[0].size();
  const int m = int(points_.size());
  const bool eliminate = preconditioner_ == UzawaPreconditioner::capacitance;
  // Deep multipliers in closed form (capacitance): λ_d = −b_d, so the right-hand side vanishes on D.
  if (eliminate)
    for (int c = 0; c < 2; ++c)
      for (std::size_t k = 0; k < g_.deep().size(); ++k) {
        const int d = g_.deep()[k];
        deep_lambda_[c][k] = -b[c][d];
        b[c][d] = 0.0;
      }
  // λ⁰ = 0: u⁰ = A⁻¹ b (b then holds u).
  A_.solve_pair(b1, b2, b1, b2);
  Eigen::VectorXd lam[2], g[2], z[2], w[2], gbar[2];
  // The stopping test, max |B u| ≤ tolerance × max |u|, on the iterate itself.
  double gz[2] = {0, 0};
  bool done[2] = {false, false};
  double field_max[2] = {max_abs(b1, n), max_abs(b2, n)};
  auto scale = [&] { return std::max({field_max[0], field_max[1], 1e-300}); };
  auto precondition = [&](const Eigen::VectorXd& r) -> Eigen::VectorXd { return eliminate ? Eigen::VectorXd(capacitance_.solve(r)) : r; };
  double residual[2] = {0, 0};
  for (int c = 0; c < 2; ++c) {
    lam[c] = Eigen::VectorXd::Zero(m);
    g[c].resize(m);
    for (int k = 0; k < m; ++k) g[c][k] = b[c][points_[k]];
    residual[c] = m == 0 ? 0.0 : g[c].cwiseAbs().maxCoeff() / scale();
    done[c] = m == 0 || residual[c] <= tolerance_;
    if (!done[c]) {
      z[c] = precondition(g[c]);
      w[c] = z[c];
      gz[c] = g[c].dot(z[c]);
    }
  }
  int it = 0;
  while (!(done[0] && done[1])) {
    if (it == max_iterations_)
      throw std::runtime_error("fictitious domain: the Uzawa CG did not converge in " + std::to_string(max_iterations_) +
                               " iterations (velocity on the obstacle " + std::to_string(std::max(residual[0], residual[1])) +
                               " of the field's scale)");
    ++it;
    // ū = A⁻¹ Bᵀ w for both components in one fast solve pair; ḡ = B ū = S w. The right-hand
    // sides (rhs_) are zero off the points and set back to zero after the solve.
    for (int c = 0; c < 2; ++c)
      if (!done[c])
        for (int k = 0; k < m; ++k) rhs_[c][std::size_t(points_[k])] = w[c][k];
    A_.solve_pair(rhs_[0].data(), rhs_[1].data(), work_[0].data(), work_[1].data());
    for (int c = 0; c < 2; ++c)
      for (int k = 0; k < m; ++k) rhs_[c][std::size_t(points_[k])] = 0.0;
    for (int c = 0; c < 2; ++c) {
      if (done[c]) continue;
      gbar[c].resize(m);
      for (int k = 0; k < m; ++k) gbar[c][k] = work_[c][std::size_t(points_[k])];
      const double alpha = gz[c] / w[c].dot(gbar[c]);
      // λ ← λ − α w, u ← u − α ū, g ← g − α ḡ.
      lam[c] -= alpha * w[c];
      field_max[c] = subtract_and_max_abs(b[c], work_[c].data(), alpha, n);
    }
    for (int c = 0; c < 2; ++c) {
      if (done[c]) continue;
      // The true residual (the velocity now on the points), not the recurrence g − α ḡ, which
      // drifts by round-off from it over many iterations.
      for (int k = 0; k < m; ++k) g[c][k] = b[c][points_[k]];
      residual[c] = g[c].cwiseAbs().maxCoeff() / scale();
      if (residual[c] <= tolerance_) {
        done[c] = true;
        continue;
      }
      z[c] = precondition(g[c]);
      const double gz_new = g[c].dot(z[c]);
      w[c] = z[c] + (gz_new / gz[c]) * w[c];
      gz[c] = gz_new;
    }
  }
  // The multiplier on C (diagnostics): λ on the CG's points (sign: Bᵀλ enters A u = b + Bᵀλ, and
  // the CG's λ is the correction −Σ α w, i.e. the multiplier itself), λ_D in closed form.
  for (int c = 0; c < 2; ++c)
    for (std::size_t k = 0; k < lambda_[c].size(); ++k) {
      const int at = where_[k];
      lambda_[c][k] = at >= 0 ? (m > 0 ? lam[c][at] : 0.0) : deep_lambda_[c][std::size_t(-at - 1)];
    }
  last_.iterations = it;
  last_.residual = std::max(residual[0], residual[1]);
  ++solves_;
  total_iterations_ += it;
  max_seen_ = std::max(max_seen_, it);
}

}  // namespace rbc
