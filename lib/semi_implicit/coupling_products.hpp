#pragma once
// The fluid solves inside one product of the semi-implicit coupling's GMRES (semi_implicit_coupling.hpp),
// and of one cell's correction A⁻¹ S (−Δt K U):
//
//   w = A⁻¹ (h² S K v)   (step 4's response to the spread force; A: step 4's operator, with the
//                          fictitious domain's constraint when the scene has one)
//   P w                  (the quasi-Stokes projection, step 1, as a fixed linear map)
//
// The caller spreads h² S K v into force_rhs() and calls response(), then project(). The two
// arrays are zero whenever they are handed out: response() clears them as its solve reads them,
// so the spreading needs no pass of its own to clear them.
//
// Precision. Where step 4 is the plain Helmholtz solve and S⁻¹ the exact fast solve (no obstacle,
// no disk, the "schur" pressure preconditioner), both run in single precision
// (SinglePeriodicBandedSolver: double in and out, the factors rounded once; the stencils,
// spreading and interpolation stay double). The product is then M K v to a relative error of a few
// 1e-7 (tests: FastSolvers.TheSinglePrecisionSolverIsTheDoubleOneToFloatRoundOff and
// CouplingProducts.*), far inside GMRES's tolerance of 1e-4, so GMRES takes the steps of the double
// products to its tolerance. One cell's correction (no GMRES) takes the same solve: a few 1e-7 of
// a velocity change that is itself a part of the step's (test: SemiImplicit.
// OneCellsCorrectionInSinglePrecisionTakesTheDoubleSteps). Elsewhere the fluid's own double
// solves are used. Precision::kDouble
// asks for those everywhere (tests, and the benchmark's comparison of the two).
#include <memory>
#include <utility>
#include <vector>

#include "fast_solvers/periodic_banded_solver.hpp"
#include "fluid/diffusion.hpp"
#include "fluid/quasi_stokes.hpp"

namespace rbc {

class CouplingProducts {
 public:
  enum class Precision { kSingleWherePossible, kDouble };
  CouplingProducts(const ChannelMesh& mesh, ImplicitDiffusion& diffusion, QuasiStokesProjection& projection, double rho, double dt,
                   Precision precision);
  // The two components' right-hand sides (interior rows j = 1..ny-1, x1 fastest), zero: the caller
  // adds h² f (N/m) into them.
  std::pair<double*, double*> force_rhs() { return {rhs1_.data(), rhs2_.data()}; }
  // out = A⁻¹ of those (m/s, zero on the walls); leaves them zero again.
  void response(VelocityField& out);
  // out = P u (the projection's exact form; out may not be u).
  void project(const VelocityField& u, VelocityField& out);
  // project's pressure alone, for P u at a few nodes (QuasiStokesProjection::projected_at; only
  // where exact_projection()); valid until the next call.
  const std::vector<double>& pressure(const VelocityField& u);
  bool exact_projection() const { return projection_.exact_schur_solve(); }
  // Whether the solves run in single precision (see the top of this file).
  bool single_precision() const { return single_helmholtz_ != nullptr; }

 private:
  ChannelMesh mesh_;
  ImplicitDiffusion& diffusion_;
  QuasiStokesProjection& projection_;
  double rho_, dt_;
  std::vector<double> rhs1_, rhs2_;
  std::vector<double> pressure_;  // the projection's
  std::unique_ptr<SinglePeriodicBandedSolver> single_helmholtz_, single_schur_;  // null: the double solves
  QuasiStokesProjection::SchurSolve schur_solve_;  // single_schur_'s solve (empty: the projection's own)
};

}  // namespace rbc
