#pragma once
// Step 4 of the Lie scheme (the study's Section 2.4) without an obstacle: implicit diffusion with forcing,
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
  // A⁻¹ in place on the two components' right-hand sides b1, b2 (interior rows j = 1..ny-1,
  // x1 fastest; walls held at 0): the plain Helmholtz solve, or the constrained one when a
  // constraint is installed. What the semi-implicit coupling's products call (coupling_products.hpp).
  void solve_pair(double* b1, double* b2);
  // x = A⁻¹ b on the interior rows j = 1..ny-1 (nx (ny−1) values, x1 fastest), walls held at 0.
  void solve_interior(double* b);
  double dt() const { return dt_; }
  // The fictitious domain (or null: no constraint, the plain Helmholtz solve). Not owned.
  void set_constraint(Step4Constraint* c) { constraint_ = c; }
  bool constrained() const { return constraint_ != nullptr; }
  // The unconstrained A⁻¹ (what the constraint's own iterations call).
  PeriodicBandedSolver& helmholtz() { return *solver_; }
  const PeriodicBandedSolver& helmholtz() const { return *solver_; }
  // The Helmholtz operator on the interior rows (what the fast solver inverts).
  PeriodicBandedSolver::Operator helmholtz_operator() const;

 private:
  Step4Constraint* constraint_ = nullptr;
  ChannelMesh m_;
  double rho_, mu_, dt_;
  std::unique_ptr<PeriodicBandedSolver> solver_;
  std::vector<double> rhs_, rhs2_;  // the two components' right-hand sides
};

}  // namespace rbc
