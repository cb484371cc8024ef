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
enum class ProjectionForm { iterative, exact };  // QuasiStokesProjection::project
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

  // P u: u projected onto the discretely divergence-free fields, into out (out may be u); p is
  // the pressure (Pa) on exit, and on entry the warm start of the iterative form. In two forms:
  //   iterative — step 1 of the scheme: CG on S p = b from p to the tolerance (with the exact
  //     Schur preconditioner the first iteration from p = 0 solves it: p = S⁻¹ b, one fast solve);
  //     a divergence at round-off level (a parallel flow) is left as it is, p = 0.
  //   exact — P as a fixed linear map (the semi-implicit coupling's GMRES products): p = S⁻¹ b in
  //     one fast solve, no residual check (the stencil sweeps of S fewer); schur_solve: z = S⁻¹ r
  //     by a caller's solver of the same S in place of the projection's own (e.g. the coupling's
  //     single-precision one: coupling_products.hpp), the mean removed from z either way. With the
  //     Laplacian preconditioner there is no exact solve: the iterative form from p = 0.
  using SchurSolve = std::function<void(const double* r, double* z)>;
  ProjectionReport project(const VelocityField& u, VelocityField& out, std::vector<double>& p, double rho, double dt,
                           ProjectionForm form, const SchurSolve& schur_solve = nullptr);
  // project in its two halves, for callers that need P u at a few nodes only (the coupling's
  // J P u at the membrane nodes): its pressure p alone (the same forms), and from it
  // (P u)(x_ij) = u + (Δt/ρ) M⁻¹ Bᵀ p on the interior, u on the walls: project's value there to
  // round-off.
  ProjectionReport pressure(const VelocityField& u, std::vector<double>& p, double rho, double dt, ProjectionForm form,
                            const SchurSolve& schur_solve = nullptr);
  void projected_at(const VelocityField& u, const std::vector<double>& p, double rho, double dt, int i, int j, double& v1,
                    double& v2) const;
  // The pressure as a nodal force density for step 4, out = M⁻¹ Bᵀ p (N/m³ for p in Pa; zero on
  // the walls): the incremental form's −∇p (channel_flow.hpp).
  void pressure_force(const std::vector<double>& p, VelocityField& out);
  // Whether S⁻¹ is the exact fast solve, and that solver (another solver of S takes its factors).
  bool exact_schur_solve() const { return exact_pc_; }
  const PeriodicBandedSolver& schur_solver() const;  // throws std::logic_error unless exact_schur_solve()

  // (B u)_Q = ∫ q_Q ∇·u_h over every coarse node (m/s · m).
  void divergence(const VelocityField& u, std::vector<double>& div) const;
  void remove_mean(std::vector<double>& p) const;

 private:
  void apply_schur(const std::vector<double>& p, std::vector<double>& out) const;
  // out = u + (Δt/ρ) M⁻¹ Bᵀ p (out may be u).
  void add_pressure_gradient(const VelocityField& u, const std::vector<double>& p, double rho, double dt, VelocityField& out);
  // z = S⁻¹ r (or the Laplacian's), mean-zero.
  void precondition(const std::vector<double>& r, std::vector<double>& z);
  // The pressure of project (rep filled in); false when u needs no correction (its divergence at
  // round-off level, p = 0).
  bool solve_pressure(const VelocityField& u, std::vector<double>& p, double rho, double dt, ProjectionForm form,
                      const SchurSolve& schur_solve, ProjectionReport& rep);

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
