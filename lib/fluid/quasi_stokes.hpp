#pragma once
// Step 1 of the Lie scheme (the study's Section 2.4): the quasi-Stokes projection, ν = 0.
//
//   find u ∈ W_0h, p ∈ L²_{h,0}:   ρ ∫ (u − uⁿ)/Δt · v − ∫ p ∇·v = 0,   ∫ q ∇·u = 0.
//
// With the lumped mass M and the divergence matrix B (fem/p1_operators.hpp) this is
//   ρ M (u − uⁿ)/Δt = Bᵀ p,   B u = 0   ⇒   S p = −(ρ/Δt) B uⁿ,   S = B M⁻¹ Bᵀ,
// then u = uⁿ + (Δt/ρ) M⁻¹ Bᵀ p on the interior nodes (walls keep their Dirichlet values).
// We solve for the pressure by preconditioned conjugate gradients (the study's Uzawa form),
// warm-started from the previous step's pressure. S is a fixed stencil on T_2h, so it can be
// inverted exactly by the fast solver ("schur", one CG iteration); the study's own choice, the
// Neumann Laplacian of T_2h, is kept as "laplacian". p is mean-zero (lumped weights of T_2h).
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "fast_solvers/periodic_banded_solver.hpp"
#include "fem/divergence_stencil.hpp"
#include "mesh/channel_mesh.hpp"

namespace rbc {

enum class PressurePreconditioner { schur, laplacian };
PressurePreconditioner parse_pressure_preconditioner(const std::string& name);  // throws on unknown

struct ProjectionReport {
  int iterations = 0;
  double residual = 0;  // ‖r‖ / ‖b‖ at exit (NaN with the exact Schur solve: not measured)
  // Whether the CG reached its tolerance (the exact Schur solve and a divergence already at
  // round-off always do); false after max_iterations or a breakdown short of it: the pressure
  // is then not the step's, and the run stops (Simulation::check_health).
  bool converged = true;
};

class QuasiStokesProjection {
 public:
  QuasiStokesProjection(const ChannelMesh& mesh, PressurePreconditioner pc, double tolerance, int max_iterations);

  // Projects u (in place) onto discretely divergence-free fields; p holds the warm start on
  // entry and the pressure (Pa) on exit.
  ProjectionReport project(VelocityField& u, std::vector<double>& p, double rho, double dt);
  // The pressure as a nodal force density for step 4, out = M⁻¹ Bᵀ p (N/m³ for p in Pa; zero on
  // the walls): the incremental form's −∇p (channel_flow.hpp).
  void pressure_force(const std::vector<double>& p, VelocityField& out);

  // The same projection as a fixed linear map, for the semi-implicit coupling's GMRES products:
  // with the exact Schur preconditioner p = S⁻¹ b in one fast solve and no residual check
  // (B, one solve, Bᵀ: two stencil sweeps fewer than project()); with the Laplacian one, project()
  // from p = 0. out = P u (out may be u).
  // schur_solve: z = S⁻¹ r in place of the projection's own fast solve (a caller's solver of the
  // same S, e.g. the coupling's single-precision one: coupling_products.hpp); only with the
  // exact Schur preconditioner. The mean is removed from z either way.
  using SchurSolve = std::function<void(const double* r, double* z)>;
  void project_exact(const VelocityField& u, VelocityField& out, double rho, double dt, const SchurSolve& schur_solve = nullptr);
  // project_exact in two parts, for callers that need P u at a few nodes only (the coupling's
  // J P u at the membrane nodes): its pressure p = S⁻¹(−(ρ/Δt) B u), mean-zero (only with the
  // exact Schur preconditioner; the reference is valid until the next call), and (P u)(x_ij) =
  // u + (Δt/ρ) M⁻¹ Bᵀ p on the interior, u on the walls: project_exact's value there to round-off.
  const std::vector<double>& exact_pressure(const VelocityField& u, double rho, double dt, const SchurSolve& schur_solve = nullptr);
  void projected_at(const VelocityField& u, const std::vector<double>& p, double rho, double dt, int i, int j, double& v1,
                    double& v2) const;
  // Whether S⁻¹ is the exact fast solve, and S itself as an operator (to build another solver of it).
  bool exact_schur_solve() const { return exact_pc_; }
  PeriodicBandedSolver::Operator schur_operator() const;

  // (B u)_Q = ∫ q_Q ∇·u_h over every coarse node (m/s · m).
  void divergence(const VelocityField& u, std::vector<double>& div) const;
  void remove_mean(std::vector<double>& p) const;

 private:
  void apply_schur(const std::vector<double>& p, std::vector<double>& out) const;
  // out = u + (Δt/ρ) M⁻¹ Bᵀ p (out may be u).
  void add_pressure_gradient(const VelocityField& u, const std::vector<double>& p, double rho, double dt, VelocityField& out);
  // z = S⁻¹ r (or the Laplacian's), mean-zero.
  void precondition(const std::vector<double>& r, std::vector<double>& z);

  ChannelMesh mesh_;
  DivergenceStencil B_;            // B and Bᵀ (Bᵀ on the interior velocity nodes only)
  double inv_mass_;                // 1/M = 1/h² on the interior nodes
  std::vector<double> weights_;    // lumped weights of T_2h for the mean
  double total_weight_ = 0;        // their sum
  std::unique_ptr<PeriodicBandedSolver> pc_;
  double tol_;
  bool exact_pc_ = false;
  double row_abs_norm_ = 0;  // ≈ ‖(Σ_n |B_qn|)_q‖₂, the scale of round-off in B u
  int max_it_;
  // Work vectors, sized once.
  mutable std::vector<double> g1_, g2_, r_, z_, d_, sd_, b_;
};

}  // namespace rbc
