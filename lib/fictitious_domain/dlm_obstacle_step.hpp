#pragma once
// Step 4 of the Lie scheme with fixed obstacles: the DLM/FD saddle-point problem (the study's
// eq. (21) with its multiplier; Glowinski, Pan, Hesla & Joseph, Int. J. Multiphase Flow 25
// (1999) 755, and Glowinski's fictitious-domain papers cited by the study). Per velocity component
// (they decouple: A acts on each alike and the constraint is u = 0 on each),
//
//   A u = b + Bᵀλ,     B u = 0,
//
// A the Helmholtz operator of step 4 ((ρh²/Δt + 4μ) − μ·(5-point sum), fluid/diffusion.hpp),
// b its right-hand side (ρh²/Δt u^{n+2/3} + h² f + wall terms), B the reading of u at the
// collocation points (obstacles.hpp), λ the multiplier (h² times the force density that holds
// the fluid in ω at rest, N/m). Eliminating u gives the Schur-complement (Uzawa) equation
//
//   S λ = −B A⁻¹ b,     S = B A⁻¹ Bᵀ   (symmetric positive definite),
//
// which we solve by conjugate gradients on λ, as the study does: each iteration applies S once,
// that is one fast Helmholtz solve (FFT in x1, banded in x2) for both components together. The
// residual of the Uzawa equation is minus the velocity on the collocation points, g = B u, and
// the iteration stops when max |g| ≤ tolerance × max |u| (the field's own scale).
//
// Preconditioners:
//  - none: the plain Uzawa CG over all collocation points (λ⁰ = 0). Its iterations grow as h
//    falls and as Δt grows (measured, see the method text paper/method/05_fictitious_domain.md).
//  - capacitance (default): the deep multipliers are set in closed form, λ_D = −b_D
//    (obstacles.hpp), and the CG runs on the ring R with S_R = (A⁻¹)_RR as its preconditioner.
//    The obstacles do not move and Δt is fixed, so S_R is computed once (one solve per pair of
//    ring nodes) and factored by Cholesky; the CG then converges in one iteration up to round-off
//    (the classical capacitance-matrix method seen as a preconditioned Uzawa iteration), and step
//    4 costs two fast solves instead of one.
#include <Eigen/Dense>
#include <vector>

#include "fictitious_domain/obstacles.hpp"
#include "fluid/diffusion.hpp"

namespace rbc {

enum class UzawaPreconditioner { capacitance, none };
UzawaPreconditioner parse_uzawa_preconditioner(const std::string& name);  // "capacitance" | "none"

class ObstacleConstraint : public Step4Constraint {
 public:
  // A: step 4's unconstrained Helmholtz solver (ImplicitDiffusion::helmholtz()); kept by reference.
  ObstacleConstraint(const ObstacleGeometry& geometry, PeriodicBandedSolver& A, double tolerance,
                     UzawaPreconditioner preconditioner, int max_iterations = 2000);
  void solve_pair(double* b1, double* b2) override;

  struct Report {
    int iterations = 0;    // CG iterations of the last solve (the larger of the two components')
    double residual = 0;   // max |u| on the collocation points after it, relative to max |u| of the field
  };
  const Report& last() const { return last_; }
  long solves() const { return solves_; }
  long total_iterations() const { return total_iterations_; }
  int max_iterations_seen() const { return max_seen_; }
  // λ of the last solve on the collocation points (geometry().nodes() order), component c, N/m.
  const std::vector<double>& multiplier(int c) const { return lambda_[c]; }
  const ObstacleGeometry& geometry() const { return g_; }
  double setup_seconds() const { return setup_seconds_; }  // building and factoring S_R

 private:
  ObstacleGeometry g_;
  PeriodicBandedSolver& A_;
  double tolerance_;
  UzawaPreconditioner preconditioner_;
  int max_iterations_;
  std::vector<int> points_;  // where the CG's λ lives: R (capacitance) or C (none)
  Eigen::LLT<Eigen::MatrixXd> capacitance_;  // of S_R
  std::vector<double> lambda_[2];
  std::vector<double> rhs_[2];   // the fast solver's right-hand sides Bᵀ w (zero off the points)
  std::vector<double> work_[2];  // and its results A⁻¹ Bᵀ w
  std::vector<double> deep_lambda_[2];  // λ_D = −b_D of the last solve (capacitance)
  std::vector<int> where_;       // per collocation node: index among points_, or −1 − index in D
  Report last_;
  long solves_ = 0, total_iterations_ = 0;
  int max_seen_ = 0;
  double setup_seconds_ = 0;
};

}  // namespace rbc
