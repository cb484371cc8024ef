#pragma once
// Step 4 of the Lie scheme (SPEC section 4) without an obstacle: implicit diffusion with forcing,
//
//   ρ ∫ (u^{n+1} − u^{n+2/3})/Δt · v + μ ∫ ∇u^{n+1} : ∇v = ∫ f · v     for all v ∈ W_0h,
//
// with u^{n+1} equal to the wall velocity on the walls. With the lumped mass (h² per interior
// node) and the P1 stiffness (the 5-point Laplacian), each velocity component solves
//
//   (ρ h²/Δt + 4μ) u_ij − μ (u_{i±1,j} + u_{i,j±1}) = (ρ h²/Δt) u^{n+2/3}_ij + h² f_ij,
//
// a Helmholtz problem solved exactly by FFT in x1 and a tridiagonal solve in x2.
#include <memory>
#include <utility>
#include <vector>

#include "fast_solvers/periodic_banded_solver.hpp"
#include "mesh/channel_mesh.hpp"

namespace rbc {

// Step 4 under a constraint on u^{n+1}: the fictitious domain's multiplier (lib/fictitious_domain)
// turns A x = b into the saddle-point problem A x = b + Bᵀλ, B x = 0. An ImplicitDiffusion with a
// constraint installed hands every solve to it; without one (no obstacle) nothing changes.
class Step4Constraint {
 public:
  virtual ~Step4Constraint() = default;
  // b1, b2 (the two components' right-hand sides on the interior rows, x1 fastest) in, x out.
  virtual void solve_pair(double* b1, double* b2) = 0;
};

class ImplicitDiffusion {
 public:
  ImplicitDiffusion(const ChannelMesh& mesh, double rho, double mu, double dt);
  // u: u^{n+2/3} in, u^{n+1} out; wall rows of u hold the wall velocities (kept).
  // force: the uniform body force (N/m³); field: an extra nodal force density (N/m³) or null.
  void diffuse(VelocityField& u, const double body_force[2], const VelocityField* field);
  // u += w, where w is step 4's response to the force density field (N/m³) alone:
  // zero on the walls, no body force, no u^{n+2/3} (A w = h² field; the step is linear in f).
  void add_force_response(VelocityField& u, const VelocityField& field);
  // The same response for callers that spread straight into the solver's right-hand sides:
  // zeroed_force_rhs() zeroes and hands out the two components' arrays (interior rows j = 1..ny-1,
  // x1 fastest), into which the caller adds h² f (N/m); force_response(out) then sets out to
  // step 4's response to that force (m/s, zero on the walls). Saves add_force_response's passes
  // over whole fields when the force is built for this only (the semi-implicit GMRES products).
  std::pair<double*, double*> zeroed_force_rhs();
  // single: the solve in single precision (build_single_precision_solver() first; unconstrained
  // only), relative error ≈ 1e-7: for the GMRES products of coupling_solves = "single".
  void force_response(VelocityField& out, bool single = false);
  void build_single_precision_solver();
  // x = A⁻¹ b on the interior rows j = 1..ny-1 (nx (ny−1) values, x1 fastest), walls held at 0.
  void solve_interior(double* b);
  double dt() const { return dt_; }
  // The fictitious domain (or null: no constraint, the plain Helmholtz solve). Not owned.
  void set_constraint(Step4Constraint* c) { constraint_ = c; }
  bool constrained() const { return constraint_ != nullptr; }
  // The unconstrained A⁻¹ (what the constraint's own iterations call).
  PeriodicBandedSolver& helmholtz() { return *solver_; }

 private:
  void solve_both(double* b1, double* b2) {
    rhs_zero_ = false;
    if (constraint_) constraint_->solve_pair(b1, b2);
    else solver_->solve_pair(b1, b2, b1, b2);
  }
  Step4Constraint* constraint_ = nullptr;
  ChannelMesh m_;
  double rho_, mu_, dt_;
  PeriodicBandedSolver::Operator helmholtz_operator() const;
  std::unique_ptr<PeriodicBandedSolver> solver_;
  std::unique_ptr<SinglePeriodicBandedSolver> single_;  // the same A⁻¹ in single precision (or null)
  std::vector<double> rhs_, rhs2_;  // the two components' right-hand sides
  bool rhs_zero_ = false;           // both are zero already (force_response cleared them as it read them)
};

}  // namespace rbc
